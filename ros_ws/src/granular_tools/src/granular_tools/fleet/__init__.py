"""run_fleet: the pipeline over many bags, on this machine or a Dask cluster (docs/fleet.md)."""
