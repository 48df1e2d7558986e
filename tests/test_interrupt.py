"""A Ctrl-C that a finaliser swallows is raised again between chunks, and the command still exits 130."""

from __future__ import annotations

import signal

import pytest

from silcount import interrupt
from silcount.mesh.chunks import run_chunks


def swallowed_ctrl_c() -> None:
    """What a finaliser does with a KeyboardInterrupt raised inside it: the interpreter drops it."""
    try:
        signal.raise_signal(signal.SIGINT)
    except KeyboardInterrupt:
        pass


def test_a_swallowed_ctrl_c_stops_the_next_chunk():
    ran: list[tuple[int, int]] = []

    def run(lo: int, hi: int) -> int:
        ran.append((lo, hi))
        if len(ran) == 1:
            swallowed_ctrl_c()
        return 0

    with interrupt.noted(), pytest.raises(KeyboardInterrupt):
        run_chunks(1000, run, first=10)
    assert ran == [(0, 10)]  # stopped before the second chunk


def test_outside_the_command_line_nothing_is_noted_or_raised_again():
    with interrupt.noted():
        swallowed_ctrl_c()
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
    interrupt.check()  # forgotten once the block is left: no stale Ctrl-C for later library calls
    run_chunks(3, lambda lo, hi: 0, first=1)


def test_the_command_exits_130_when_the_ctrl_c_came_after_the_last_chunk(monkeypatch, capsys):
    from silcount.cli import main as cli

    def run(args) -> int:
        swallowed_ctrl_c()
        return 0

    parser = cli.build_parser()
    args = parser.parse_args(["audit", "icosahedron"])
    monkeypatch.setattr(cli, "build_parser", lambda: type("P", (), {"parse_args": lambda self, a: args})())
    monkeypatch.setattr(args, "_run", run, raising=False)
    assert cli.main(["audit", "icosahedron"]) == 130
    assert capsys.readouterr().err == "silcount: interrupted\n"
