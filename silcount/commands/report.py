"""`silcount report` (not yet implemented)."""
from __future__ import annotations

import argparse

from ..errors import BadArgument

HELP = "report (not yet implemented)"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    pass


def run(args: argparse.Namespace) -> int:
    raise BadArgument("'report' is not implemented yet")
