"""Watching the online nodes: what they publish, against the ground truth."""
