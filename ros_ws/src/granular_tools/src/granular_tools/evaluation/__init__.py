"""Evaluation: metrics of classification results and the report that compares the methods."""
