"""Motion between the frames of a sequence (ALGORITHM §9)."""
