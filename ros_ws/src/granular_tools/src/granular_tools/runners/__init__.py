"""The runners on top of the tools: each chains tools into one run (run_pipeline, run_cuboids,
run_evaluation, evaluate_many), with what they share in `stages`."""
