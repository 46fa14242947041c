"""Class models: pictures of the models that granular_ros build_models writes."""
