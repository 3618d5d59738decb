"""Painting on a Dask cluster: a sequence's frames and a batch of stills spread over worker processes."""
