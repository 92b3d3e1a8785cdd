"""Slider joints on rigid curves and on chains of deformable beams (paper Secs. 3-4)."""
