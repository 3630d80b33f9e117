"""Batch layer: many grasps at once — records, sampling, grasp files, evaluation on local
processes (a pool that survives its workers), Ray or Dask, typed row statuses and reasons, a
row journal with resume, atomic result tables (docs/batch.md)."""
