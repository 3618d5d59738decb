"""Sequences: painting a shot with strokes that live across frames (ALGORITHM §9)."""
