"""`silcount figures` (not yet implemented)."""
from __future__ import annotations

import argparse

from ..errors import BadArgument

HELP = "figures (not yet implemented)"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    pass


def run(args: argparse.Namespace) -> int:
    raise BadArgument("'figures' is not implemented yet")
