"""Counting arithmetic, by hand: every operator counts one operation of its kind and computes the right value.

Every ``true`` tally of every ``naive`` engine is made of these counts, so each
rule is checked on its own (found by mutation testing: the detectors' tests use
only some operators, e.g. ``x - Num``, ``/`` and ``<`` appear only in EESD and
the coplanar merge).
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

from silcount.counting.arithmetic import KINDS, Memory, Num, OpCounter, plain


def test_each_operator_counts_one_of_its_kind():
    c = OpCounter()
    x, y = Num(7.0, c), Num(2.0, c)
    cases = [
        (lambda: x + y, "add", 9.0),
        (lambda: 1.0 + x, "add", 8.0),
        (lambda: x - y, "add", 5.0),
        (lambda: 10.0 - x, "add", 3.0),
        (lambda: x * y, "mul", 14.0),
        (lambda: 3.0 * x, "mul", 21.0),
        (lambda: x / y, "div", 3.5),
        (lambda: 14.0 / x, "div", 2.0),
    ]
    for op, kind, value in cases:
        before = dict(c)
        out = op()
        assert isinstance(out, Num) and out.value == value and out.counter is c
        after = dict(c)
        assert {k: after.get(k, 0) - before.get(k, 0) for k in after} == {k: int(k == kind) for k in after}, kind


@pytest.mark.parametrize(
    "a, b, expected",
    [(1.0, 2.0, (True, True, False, False, False, True)), (2.0, 2.0, (False, True, False, True, True, False)),
     (3.0, 2.0, (False, False, True, True, False, True))],
)  # fmt: skip
def test_comparisons_count_one_compare_each_and_are_exact(a, b, expected):
    c = OpCounter()
    x = Num(a, c)
    got = (x < b, x <= b, x > b, x >= b, x == b, x != b)
    assert got == expected and all(type(g) is bool for g in got)
    assert dict(c) == {"cmp": 6}


def test_memory_counts_reads_and_writes_and_returns_python_scalars():
    c = OpCounter()
    m = Memory(np.array([1, 2, 3], dtype=np.int64), c)
    v = m[1]
    assert type(v.value) is int and v.value == 2 and dict(c) == {"read": 1}
    m[0] = Num(5, c)
    m[2] = 9
    assert m.data.tolist() == [5, 2, 9] and c["write"] == 2 and c["read"] == 1
    assert len(m) == 3
    frac = Memory([Fraction(1, 3)], c)  # a list stays a list (exact values are not converted)
    assert isinstance(frac.data, list) and frac[0].value == Fraction(1, 3) and c["read"] == 2


def test_tick_plain_and_no_hash():
    c = OpCounter()
    c.tick("add")
    c.tick("add")
    c.tick("read", 3)
    assert dict(c) == {"add": 2, "read": 3}
    assert plain(Num(4, c)) == 4 and plain(4) == 4
    with pytest.raises(TypeError):
        hash(Num(1, c))
    assert repr(Num(1.5, c)) == "Num(1.5)"
    assert KINDS == ("add", "mul", "cmp", "read", "write")
