"""Mask PNGs and their comparison (scene README, "The mask" and "Comparing two masks").

A mask is an 8-bit grayscale PNG, 255 in shadow and 0 elsewhere; a coverage
PNG is 255 where the sample hits a surface.  Reading accepts any PNG mode
and thresholds at 128.  Files are written atomically (temporary file in the
same directory, then ``os.replace``: :mod:`silcount.atomic`).

Comparison: mismatches as a fraction of covered pixels (all pixels when no
coverage is given), and the *far* mismatches: those more than one pixel
(8-neighbourhood) from an edge pixel of either mask, an edge pixel being
one whose value differs from one of its 8 neighbours.  Both are :mod:`scipy.ndimage`
morphology with a 3x3 square: the edge pixels are where the 3x3 maximum and
minimum differ, with the pixels past the border repeating the border
(``mode="nearest"``, so the border is not an edge by itself); the dilation
treats the pixels past the border as false (``border_value=0``).  scipy is
imported by the comparison alone (~0.3 s), so writing a mask never loads it.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from PIL import Image, UnidentifiedImageError

from silcount.atomic import atomic_path
from silcount.errors import BadArgument, UnreadableInput


def write_png(path: str | os.PathLike, pixels: np.ndarray) -> Path:
    """Write a (H, W) uint8 or (H, W, 3) uint8 image atomically (missing folders created); returns the path."""
    p = Path(path)
    with atomic_path(p) as tmp:
        Image.fromarray(np.ascontiguousarray(pixels)).save(tmp, format="PNG", optimize=False)
    return p


def write_mask(path: str | os.PathLike, mask: np.ndarray) -> Path:
    """A boolean mask as an 8-bit grayscale PNG (255 = true)."""
    return write_png(path, np.where(np.asarray(mask, dtype=bool), 255, 0).astype(np.uint8))


def read_mask(path: str | os.PathLike) -> np.ndarray:
    """(H, W) bool from a PNG (gray >= 128); :class:`UnreadableInput` naming the file otherwise."""
    p = Path(path)
    try:
        with Image.open(p) as im:
            im.load()
            gray = np.asarray(im.convert("L"))
    except FileNotFoundError:
        raise UnreadableInput(f"{p}: no such file") from None
    except IsADirectoryError:
        raise UnreadableInput(f"{p}: is a directory, not a PNG") from None
    except (UnidentifiedImageError, OSError, ValueError) as exc:
        raise UnreadableInput(f"{p}: not a readable image: {exc}") from None
    return gray >= 128


SQUARE = np.ones((3, 3), dtype=bool)  # the 8-neighbourhood and the pixel itself


def _plane(mask: np.ndarray) -> np.ndarray:
    m = np.asarray(mask)
    if m.ndim != 2:
        raise ValueError(f"a mask is a (H, W) array, got shape {m.shape}")
    return m


def edge_pixels(mask: np.ndarray) -> np.ndarray:
    """Pixels whose value differs from one of their 8 neighbours (past the border: the border repeated)."""
    from scipy import ndimage

    m = _plane(mask)
    high = ndimage.grey_dilation(m, size=(3, 3), mode="nearest")
    return high != ndimage.grey_erosion(m, size=(3, 3), mode="nearest")


def dilate(mask: np.ndarray) -> np.ndarray:
    """3x3 dilation (past the border: false)."""
    from scipy import ndimage

    return ndimage.binary_dilation(_plane(mask), structure=SQUARE, iterations=1, border_value=0)


@dataclass
class Comparison:
    covered: int
    mismatched: int
    far: int  # mismatches more than one pixel from any edge of either mask
    tol: float

    @property
    def fraction(self) -> float:
        return self.mismatched / self.covered if self.covered else 0.0

    @property
    def ok(self) -> bool:
        return self.far == 0 and self.fraction <= self.tol

    def describe(self) -> str:
        return (
            f"{self.mismatched} of {self.covered} covered pixels differ ({self.fraction:.6f}, tolerance {self.tol}); "
            f"{self.far} of them more than one pixel from an edge of either mask"
        )


def compare_masks(a: np.ndarray, b: np.ndarray, coverage: np.ndarray | None = None, tol: float = 0.005) -> Comparison:
    """Compare two boolean masks (see module docstring)."""
    if a.shape != b.shape or (coverage is not None and coverage.shape != a.shape):
        shapes = [a.shape, b.shape] + ([coverage.shape] if coverage is not None else [])
        raise BadArgument(f"masks must have the same size, got {' vs '.join(str(s[::-1]) for s in shapes)} (W, H)")
    cov = np.ones_like(a, dtype=bool) if coverage is None else coverage
    diff = (a != b) & cov
    near = dilate(edge_pixels(a) | edge_pixels(b))
    return Comparison(int(cov.sum()), int(diff.sum()), int((diff & ~near).sum()), float(tol))
