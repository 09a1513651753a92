"""Design-space studies: a study file (:mod:`studies.study`) run over a grid of stators on
dask.distributed, resumable, into one labelled dataset (:mod:`studies.explore`)."""
