"""Geometric shapes for constraints."""
import numpy as np


class Wall:
    """A plane: points x with normal . x - dist > 0 are on its fluid side.

    Parameters: normal (3-vector, normalised internally), dist (float).
    """

    def __init__(self, normal=(0.0, 0.0, 1.0), dist=0.0):
        n = np.asarray(normal, dtype=float)
        if n.shape != (3,) or not np.all(np.isfinite(n)) or not np.linalg.norm(n) > 0:
            raise ValueError("parameter 'normal' must be a finite non-zero 3-vector")
        if not np.isfinite(float(dist)):
            raise ValueError("parameter 'dist' must be finite")
        self.normal = n / np.linalg.norm(n)
        self.dist = float(dist)

    def calc_dist(self, pos):
        """Signed distance of a point from the wall (positive on the fluid side)."""
        return float(np.dot(self.normal, np.asarray(pos, dtype=float)) - self.dist)

    def __repr__(self):
        return f"Wall(normal={self.normal.tolist()}, dist={self.dist})"
