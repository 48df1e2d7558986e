"""The Triangular Algorithm: hand-counted tallies, the paper's printed sum, naive == fast, agreement."""

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from strategies import any_meshes, closed_meshes, examples, lights_for, mesh_and_light

import silcount
from silcount.counting import models
from silcount.detectors.base import visibility_true_cost
from silcount.mesh.model import from_polygons
from silcount.testing import assert_silhouettes_equal

# One counted_visibility with a point light, by hand: reads face_start[p] (1), three corner
# indices (3), nine coordinates (9), three light coordinates (3) = 16 R; e1, e2 (6 A), the cross
# product (6 M, 3 A), L - p0 (3 A), the dot product (3 M, 2 A) = 14 A, 9 M; the sign test 1 C.
VIS_POINT = {"read": 16, "add": 14, "mul": 9, "cmp": 1}


def test_visibility_cost_by_hand():
    assert visibility_true_cost(silcount.PointLight((0, 0, 5))) == VIS_POINT
    # directional: no L - p0 (3 A fewer)
    assert visibility_true_cost(silcount.DirectionalLight((0, 0, 1))) == {**VIS_POINT, "add": 11}


def _tetra():
    m = silcount.builtin_mesh("tetrahedron")
    # welding sorts the vertices: (-1,-1,1)=0, (-1,1,-1)=1, (1,-1,-1)=2, (1,1,1)=3
    assert m.corners.reshape(-1, 3).tolist() == [[3, 2, 1], [3, 0, 2], [3, 1, 0], [2, 0, 1]]
    return m


def test_tetrahedron_by_hand():
    # Light at (5,5,5), beyond the apex 3: faces 0, 1, 2 face it, face 3 (the base) does not.
    # V = 4, key(a->b) = 4a + b.  S after each side ("search length" = elements read and compared):
    # face 0 [3,2,1]: 3->2 seek 2->3 in [] (0) add;          2->1 seek 1->2 in [32] (1) add;
    #                 1->3 seek 3->1 in [32,21] (2) add                         -> S = [32,21,13]
    # face 1 [3,0,2]: 3->0 seek 0->3 (3) add; 0->2 seek 2->0 (4) add            -> [32,21,13,30,02]
    #                 2->3 seek 3->2: found at 0 (1); delete shifts 4 left      -> [21,13,30,02]
    # face 2 [3,1,0]: 3->1 seek 1->3: found at 1 (2); shifts 2                  -> [21,30,02]
    #                 1->0 seek 0->1 (3) add                                    -> [21,30,02,10]
    #                 0->3 seek 3->0: found at 1 (2); shifts 2                  -> [21,02,10]
    # searches 9, examined 0+1+2+3+4+1+2+3+2 = 18, deletes 3, adds 6, shifted 4+2+2 = 8.
    m = _tetra()
    light = silcount.PointLight((5.0, 5.0, 5.0))
    for engine in ("naive", "fast"):
        res = silcount.detect(m, light, "ta", engine=engine)
        assert res.oriented.tolist() == [[1, 0], [0, 2], [2, 1]]  # rows follow the edge table
        assert res.edges.tolist() == [[0, 1], [0, 2], [1, 2]]
        assert res.notes["S_length"] == 3 and res.notes["duplicates_in_S"] == 0  # S = [21, 02, 10]
        assert res.steps == {"visibility": 4, "search_S": 9, "delete": 3, "add": 6, "shift": 8}
        # true: 4 visibilities (4 x VIS_POINT); 3 facing faces read face_start twice (6 R);
        # 9 sides read v_p, v_q (18 R) and pack the reverse key (9 M, 9 A); 18 elements read and
        # compared (18 R, 18 C); 3 deletes decrement the length (3 A) and shift 8 (8 R, 8 W);
        # 6 adds pack the key (6 M, 6 A), write it (6 W) and increment the length (6 A).
        assert res.tally["true"] == {
            "read": 64 + 6 + 18 + 18 + 8,
            "add": 56 + 9 + 3 + 12,
            "mul": 36 + 9 + 6,
            "cmp": 4 + 18,
            "write": 8 + 6,
        }
        # paper (EESD 5.1, e_n = 6): 4 x (8A 10M 1C 8R); 9 searches x (6C 6R 1M); 3 deletes x
        # (1R 2W); 6 adds x 1W.
        assert res.tally["paper"] == {"add": 32, "mul": 40 + 9, "cmp": 4 + 54, "read": 32 + 54 + 3, "write": 6 + 6}


def test_quad_cube_by_hand():
    # Light (0,0,10): only the top quad [1,5,7,3] faces it (facing value 9.5; the sides -0.5,
    # the bottom -10.5).  Its 4 sides search an S of length 0, 1, 2, 3 (6 examined), all absent:
    # 4 adds, S = [1->5, 5->7, 7->3, 3->1].
    m = silcount.builtin_mesh("quad_cube")
    light = silcount.PointLight((0.0, 0.0, 10.0))
    for engine in ("naive", "fast"):
        res = silcount.detect(m, light, "ta", engine=engine)
        assert res.edges.tolist() == [[1, 3], [1, 5], [3, 7], [5, 7]]
        assert res.oriented.tolist() == [[3, 1], [1, 5], [7, 3], [5, 7]]
        assert res.steps == {"visibility": 6, "search_S": 4, "delete": 0, "add": 4, "shift": 0}
        # true: 6 x VIS_POINT; 1 facing face (2 R); 4 sides (8 R, 4 M, 4 A); 6 examined (6 R, 6 C);
        # 4 adds (4 M, 8 A, 4 W)
        assert res.tally["true"] == {
            "read": 96 + 2 + 8 + 6,
            "add": 84 + 4 + 8,
            "mul": 54 + 4 + 4,
            "cmp": 6 + 6,
            "write": 4,
        }
        # paper (e_n = 12): 6 x (8A 10M 1C 8R); 4 searches x (12C 12R 1M); 4 adds x 1W
        assert res.tally["paper"] == {"add": 48, "mul": 60 + 4, "cmp": 6 + 48, "read": 48 + 48, "write": 4}


def test_literal_start_by_hand():
    # literal: S starts with the 12 cube edges in edge-table order, each lower -> higher:
    # [01,02,04,13,15,23,26,37,45,46,57,67].  The top quad's sides, light (0,0,10):
    #   1->5 seeks 5->1: absent (12 examined), appended (length 13; a second copy of 15)
    #   5->7 seeks 7->5: absent (13 examined), appended (length 14; a second copy of 57)
    #   7->3 seeks 3->7: position 7 (8 examined), deleted, 14 - 8 = 6 shifted (length 13)
    #   3->1 seeks 1->3: position 3 (4 examined), deleted, 13 - 4 = 9 shifted (length 12)
    # S keeps 10 distinct edges (all but 13 and 37), two of them twice.  The reference's 4 top
    # edges are 13, 15, 37, 57: literal misses 13 and 37 and adds 8 that are not silhouettes.
    m = silcount.builtin_mesh("quad_cube")
    light = silcount.PointLight((0.0, 0.0, 10.0))
    for engine in ("naive", "fast"):
        res = silcount.detect(m, light, "ta", variant="literal", engine=engine)
        assert res.steps == {"visibility": 6, "search_S": 4, "delete": 2, "add": 2, "shift": 6 + 9, "init_S": 12}
        assert res.n_edges == 10 and res.notes["duplicates_in_S"] == 2 and res.notes["S_length"] == 12
        assert res.agreement["missed_edges"] == 2 and res.agreement["extra_edges"] == 8
        # true, beyond the intended run's visibility (6 x VIS_POINT) and facing face (2 R):
        # init 12 x (2R 1M 2A 1W); 4 sides (8R 4M 4A); examined 12+13+8+4 = 37 (37R 37C);
        # 2 deletes (2A) shifting 15 (15R 15W); 2 adds (2M 4A 2W)
        assert res.tally["true"] == {
            "read": 96 + 2 + 24 + 8 + 37 + 15,
            "add": 84 + 24 + 4 + 2 + 4,
            "mul": 54 + 12 + 4 + 2,
            "cmp": 6 + 37,
            "write": 12 + 15 + 2,
        }


def test_defaults_are_the_intended_variant_and_the_fast_engine():
    from silcount.detectors import ta

    res = ta.detect(_tetra(), silcount.PointLight((5.0, 5.0, 5.0)))
    assert (res.variant, res.engine, res.n_edges) == ("intended", "fast", 3)


def test_paper_worst_case_reproduces_printed_sum():
    # EESD 5.1 / HSD 6.1: f_n(8A+10M+1C+8R+(m(e_n C+e_n R+1M+1R+2W))) with e_n = 6n: the sum
    # charges every face's visibility and every side's search and delete (1R+2W), never the add.
    n, m = 10, 3
    steps = {"visibility": n, "search_S": n * m, "delete": n * m, "add": 0}
    got = models.paper_tally("eesd2012-ta", steps, {"f_n": n, "e_n": 6 * n, "m": m})
    # first printed line at n = 10, m = 3: A 8n = 80; M 10n + mn = 130; C n + 6n.mn = 10 + 1800;
    # R 8n + 6n.mn + mn = 80 + 1800 + 30; W 2mn = 60.  (The printed last line, 6n^2mC, drops n.1C.)
    assert got == {"add": 80, "mul": 130, "cmp": 1810, "read": 1910, "write": 60}
    assert models.paper_tally("hsd2011-ta", steps, {"f_n": n, "e_n": 6 * n, "m": m}) == got


SETTINGS = settings(max_examples=examples(20), deadline=None, suppress_health_check=[HealthCheck.too_slow])


@SETTINGS
@given(data=st.data(), variant=st.sampled_from(["intended", "literal"]))
def test_naive_equals_fast_closed(data, variant):
    mesh = data.draw(closed_meshes())
    light = data.draw(lights_for(mesh))
    naive, fast = (silcount.detect(mesh, light, "ta", variant, engine) for engine in ("naive", "fast"))
    assert_silhouettes_equal(naive, fast, check_engine=False)


@SETTINGS
@given(data=st.data(), variant=st.sampled_from(["intended", "literal"]))
def test_naive_equals_fast_any_mesh(data, variant):
    mesh = data.draw(any_meshes())
    light = data.draw(lights_for(mesh))
    naive, fast = (silcount.detect(mesh, light, "ta", variant, engine) for engine in ("naive", "fast"))
    assert_silhouettes_equal(naive, fast, check_engine=False)


@settings(max_examples=examples(40), deadline=None)
@given(ml=mesh_and_light())
def test_intended_equals_reference_on_closed_meshes(ml):
    mesh, light = ml
    ta = silcount.detect(mesh, light, "ta")
    ref = silcount.detect(mesh, light, "reference")
    assert np.array_equal(ta.edges, ref.edges) and np.array_equal(ta.oriented, ref.oriented)
    assert ta.notes["duplicates_in_S"] == 0


def test_inconsistent_winding_leaves_a_duplicate():
    # two triangles folded on the edge (0,0,0)-(1,0,0), both traversing it the same way and both
    # lit from +z: TA cannot cancel them and appends the edge twice; the reference (two facing
    # faces) does not call it a silhouette edge.
    v = np.array([[0, 0, 0], [1, 0, 0], [0.5, 1, 0], [0.5, 1, 0.5]])
    m = from_polygons(v, [[0, 1, 2], [0, 1, 3]])
    assert m.inconsistent_edges.size == 1
    res = silcount.detect(m, silcount.DirectionalLight((0, 0, 1)), "ta")
    assert res.n_edges == 5 and res.notes["duplicates_in_S"] == 1
    assert res.agreement["extra_edges"] == 1 and res.agreement["missed_edges"] == 0


def plain_list_replay(start, keys, facing, initial):
    """TA's S as a Python list searched from the front: final S, elements examined, elements shifted."""
    S, examined, shifted = list(initial), 0, 0
    for p in np.flatnonzero(facing):
        for k in keys[start[p] : start[p + 1]]:
            rev = k ^ 1
            if rev in S:
                pos = S.index(rev)
                examined += pos + 1
                shifted += len(S) - pos - 1
                del S[pos]
            else:
                examined += len(S)
                S.append(k)
    return S, examined, shifted


@settings(max_examples=examples(200), deadline=None)
@given(n_keys=st.integers(2, 12), data=st.data())
def test_replay_matches_a_plain_list(n_keys, data):
    # The Fenwick replay against S as a Python list searched from the front, on arbitrary key
    # sequences (duplicates, any initial content): same final S, same search and shift counts.
    from silcount.detectors.edge_array import replay

    sizes = data.draw(st.lists(st.integers(0, 5), min_size=1, max_size=12))
    start = np.concatenate([[0], np.cumsum(sizes)]).astype(np.int64)
    keys = np.array(
        data.draw(st.lists(st.integers(0, n_keys - 1), min_size=int(start[-1]), max_size=int(start[-1]))),
        dtype=np.int64,
    )
    facing = np.array(data.draw(st.lists(st.booleans(), min_size=len(sizes), max_size=len(sizes))))
    initial = np.array(data.draw(st.lists(st.integers(0, n_keys - 1), max_size=20)), dtype=np.int64)
    S, examined, shifted = plain_list_replay(start, keys, facing, initial)
    r = replay(start, keys, facing, n_keys + (n_keys % 2), initial)
    assert r.live_keys.tolist() == S and r.examined == examined and r.shifted == shifted


@pytest.mark.parametrize("seed", range(4))
def test_replay_matches_a_plain_list_over_many_words(seed):
    # The replay counts deleted slots by one bit each, 64 to a word, and a Fenwick tree over the words:
    # sequences of a few thousand slots reach deletions in hundreds of words and across word boundaries.
    from silcount.detectors.edge_array import replay

    rng = np.random.default_rng(seed)
    n_keys = 2 * int(rng.integers(50, 400))
    sizes = rng.integers(0, 6, int(rng.integers(500, 1500)))
    start = np.concatenate([[0], np.cumsum(sizes)]).astype(np.int64)
    keys = rng.integers(0, n_keys, int(start[-1])).astype(np.int64)
    facing = rng.random(sizes.size) < 0.7
    initial = rng.integers(0, n_keys, int(rng.integers(0, 300))).astype(np.int64)
    S, examined, shifted = plain_list_replay(start, keys, facing, initial)
    r = replay(start, keys, facing, n_keys, initial)
    assert r.live_keys.tolist() == S and r.examined == examined and r.shifted == shifted
    assert r.deleted > 200 and initial.size + r.added > 64 * 10  # deletions over ten words and more


def test_replay_refuses_more_slots_than_its_int32_indices_hold():
    # S's replay keeps slots and keys as int32; a mesh needing more is refused, naming the limit, before any
    # allocation (no wrapped index).
    from silcount.detectors.edge_array import MAX_SLOTS, replay

    with pytest.raises(ValueError, match="2,147,483,647"):
        replay(np.zeros(1, dtype=np.int64), np.zeros(0, dtype=np.int64), np.zeros(0, dtype=bool), MAX_SLOTS + 1)
    assert replay(np.zeros(1, dtype=np.int64), np.zeros(0, dtype=np.int64), np.zeros(0, dtype=bool), 4).searched == 0
