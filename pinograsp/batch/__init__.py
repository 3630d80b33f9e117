"""Batch layer: many grasps at once — records, sampling, grasp files, evaluation on local
processes, Ray or Dask, result tables (docs/batch.md)."""
