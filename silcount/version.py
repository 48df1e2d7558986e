"""silcount's version, in one place: ``pyproject.toml`` reads it from here (``dynamic = ["version"]``).

A plain constant rather than ``importlib.metadata.version("silcount")``: that import costs ~50 ms in every
process (``silcount render`` included) and gives ``0+unknown`` in a source tree that was never installed.
"""

from __future__ import annotations

__version__ = "0.1.0"
