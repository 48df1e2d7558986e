"""The Triangular Algorithm's array S of directed edges, in two engines.

HSD paper Sec. IV 4.1 and EESD paper Sec. 3.1 keep the candidate silhouette
edges in "an array of edges (S)" that is searched "from the first of the
array"; a found edge is deleted, a missing one is appended.  Both TA and HSD
(TA over merged polygons) run on this module.

* :class:`CountedEdgeArray` is S on counting memory (the ``naive`` engines):
  each directed edge is one packed integer key ``from * V + to``; a search
  reads and compares elements from the front and stops at the first match;
  a deletion shifts every element behind it one place left (one read and one
  write each) and decrements the length; an append writes one element and
  increments the length.  The length is a :class:`~silcount.counting.arithmetic.Num`, so
  its updates count one ``add`` each; the search loop's bound test is loop
  bookkeeping (not counted).
* :func:`replay` computes the same outcome and the same counts without the
  quadratic scan (the ``fast`` engines): S is a sequence of insertion slots;
  the position of a live element is the number of elements inserted before
  it less those of them already deleted, the deletions kept as one bit per
  slot with a Fenwick tree over the counts of 64-slot words (an append takes
  the next slot and touches neither); the live slots of each directed edge form
  a FIFO queue (a search finds the front-most match, i.e. the oldest live
  copy; appends go to the back), so duplicates, non-manifold edges and
  inconsistent winding are replayed exactly as the array would behave.

Directed edges are identified in :func:`replay` by ``2 * edge_id + dir``
(``dir = 0`` for lower -> higher vertex index), so the reverse of key ``k``
is ``k ^ 1``; this is a relabelling of the packed keys, not a different rule.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass

import numpy as np
from numba import njit

from silcount.counting.arithmetic import Memory, Num, OpCounter
from silcount.detectors.adjacency import facing_range
from silcount.detectors.base import on_threads
from silcount.mesh.lights import Light
from silcount.mesh.model import Mesh


class CountedEdgeArray:
    """S as counted memory: packed directed-edge keys, searched from the front."""

    def __init__(self, capacity: int, counter: OpCounter) -> None:
        self.data = Memory(np.zeros(max(capacity, 1), dtype=np.int64), counter)
        self.length = Num(0, counter)

    def find(self, key: Num) -> int:
        """Position of the first element equal to ``key``, else -1 (reads and compares up to it)."""
        for i in range(self.length.value):
            if self.data[i] == key:
                return i
        return -1

    def delete(self, pos: int) -> None:
        """Remove the element at ``pos``, keeping order: the elements behind it move left."""
        for j in range(pos + 1, self.length.value):
            self.data[j - 1] = self.data[j]
        self.length = self.length - 1

    def append(self, key: Num) -> None:
        self.data[self.length.value] = key
        self.length = self.length + 1

    def keys(self) -> np.ndarray:
        """The live keys in array order (uncounted: this is the output)."""
        return np.asarray(self.data.data[: self.length.value], dtype=np.int64)


@dataclass
class Replay:
    """The outcome of running TA's array S over a sequence of sides."""

    live_keys: np.ndarray  # directed keys (2*edge + dir) left in S, in array order
    searched: int  # sides searched (one search per side of a light-facing polygon)
    examined: int  # elements read and compared by all searches
    deleted: int  # searches that found the reverse edge
    added: int  # searches that did not
    shifted: int  # elements moved left by deletions


MAX_SLOTS = 2**31 - 1
"""S's slots and directed keys are int32 in the replay: a mesh beyond it (a billion edges) is refused."""


def _replay_input(start, side_key, n_keys: int, initial) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The replay's CSR starts, side keys and initial keys as contiguous int64 (no initial keys: empty),
    refused by name beyond :data:`MAX_SLOTS`."""
    init = np.zeros(0, dtype=np.int64) if initial is None else np.ascontiguousarray(initial, dtype=np.int64)
    side_key = np.ascontiguousarray(side_key, dtype=np.int64)
    if max(int(n_keys), int(side_key.size) + int(init.size)) > MAX_SLOTS:
        raise ValueError(f"S's replay holds at most {MAX_SLOTS:,} slots and keys; this mesh needs more")
    return np.ascontiguousarray(start, dtype=np.int64), side_key, init


@njit(cache=True, inline="always")
def _enqueue(s, key, slot_key, alive, head, tail, nxt):  # pragma: no cover - compiled
    """Slot ``s`` now holds a live copy of ``key``, last in that key's queue of copies."""
    slot_key[s] = key
    alive[s] = True
    if head[key] < 0:
        head[key] = s
    else:
        nxt[tail[key]] = s
    tail[key] = s


_M1 = np.uint64(0x5555555555555555)
_M2 = np.uint64(0x3333333333333333)
_M4 = np.uint64(0x0F0F0F0F0F0F0F0F)
_H01 = np.uint64(0x0101010101010101)


@njit(cache=True, inline="always")
def popcount(x):  # pragma: no cover - compiled
    """Set bits of a uint64 (the SWAR sum of bit pairs, nibbles and bytes)."""
    x = x - ((x >> np.uint64(1)) & _M1)
    x = (x & _M2) + ((x >> np.uint64(2)) & _M2)
    x = (x + (x >> np.uint64(4))) & _M4
    return np.int64((x * _H01) >> np.uint64(56))


@njit(cache=True)
def _replay(start, side_key, poly_facing, n_keys, initial):  # pragma: no cover - compiled
    """S's searches over slots in insertion order.  A slot's place in S is its slot number less the deleted
    slots before it; those are counted by one bit per slot, 64 to a word, and a Fenwick tree over the words'
    counts, so an insertion (always the next slot) touches neither."""
    n_init = initial.size
    n_sides = 0
    for p in range(poly_facing.size):
        if poly_facing[p]:
            n_sides += start[p + 1] - start[p]
    n_slots = n_init + n_sides
    n_words = (n_slots >> 6) + 1
    dead_bits = np.zeros(n_words, dtype=np.uint64)
    dead = np.zeros(n_words + 1, dtype=np.int64)  # Fenwick tree over words (1-based): deleted slots in each
    alive = np.zeros(n_slots, dtype=np.bool_)
    # int32 slots and keys (:data:`MAX_SLOTS`): half the bytes of the random accesses, 1.6-1.9x faster
    slot_key = np.empty(n_slots, dtype=np.int32)
    nxt = np.full(n_slots, -1, dtype=np.int32)  # next live slot with the same key
    head = np.full(n_keys, -1, dtype=np.int32)
    tail = np.full(n_keys, -1, dtype=np.int32)
    for s in range(n_init):
        _enqueue(s, initial[s], slot_key, alive, head, tail, nxt)
    size = n_init
    used = n_init
    searched = 0
    examined = 0
    deleted = 0
    shifted = 0
    for p in range(poly_facing.size):
        if not poly_facing[p]:
            continue
        for q in range(start[p], start[p + 1]):
            key = side_key[q]
            rev = key ^ 1
            searched += 1
            s = head[rev]
            if s >= 0:
                w = s >> 6
                bit = np.uint64(1) << np.uint64(s & 63)
                pos = s - popcount(dead_bits[w] & (bit - np.uint64(1)))  # live slots before s
                i = w
                while i > 0:  # the deleted slots of words 0 .. w - 1
                    pos -= dead[i]
                    i -= i & -i
                examined += pos + 1
                shifted += size - pos - 1
                dead_bits[w] |= bit
                i = w + 1
                while i <= n_words:
                    dead[i] += 1
                    i += i & -i
                alive[s] = False
                head[rev] = nxt[s]
                if head[rev] < 0:
                    tail[rev] = -1
                size -= 1
                deleted += 1
            else:
                examined += size
                _enqueue(used, key, slot_key, alive, head, tail, nxt)
                used += 1
                size += 1
    live = slot_key[:used][alive[:used]].astype(np.int64)
    return live, searched, examined, deleted, used - n_init, shifted


def replay(
    start: np.ndarray, side_key: np.ndarray, poly_facing: np.ndarray, n_keys: int, initial: np.ndarray | None = None
) -> Replay:
    """Run S over polygons in order: for each light-facing polygon, each side's key, search its reverse.

    ``start`` (P+1,) CSR offsets into ``side_key`` (directed keys ``2*edge+dir``);
    ``initial`` the keys S holds before the loop (the ``literal`` TA start).
    """
    start, side_key, init = _replay_input(start, side_key, n_keys, initial)
    live, searched, examined, deleted, added, shifted = _replay(
        start, side_key, np.ascontiguousarray(poly_facing, dtype=np.bool_), int(n_keys), init
    )
    return Replay(live, int(searched), int(examined), int(deleted), int(added), int(shifted))


@njit(cache=True, nogil=True)
def _facing_replay(start, side_key, p0, nrm, light, directional, n_keys, initial):  # pragma: no cover - compiled
    """One light: the polygons' facing flags and ties (:func:`.adjacency.facing_flags`' arithmetic), then
    :func:`_replay` over them; the GIL released, so that lights run on threads side by side."""
    flags = np.empty(p0.shape[0], dtype=np.bool_)
    ties = facing_range(p0, nrm, light, directional, flags, 0, p0.shape[0])
    return (flags, ties) + _replay(start, side_key, flags, n_keys, initial)


def replay_many(
    start: np.ndarray,
    side_key: np.ndarray,
    p0: np.ndarray,
    nrm: np.ndarray,
    lights: list[Light],
    n_keys: int,
    initial: np.ndarray | None = None,
) -> list[tuple[np.ndarray, int, Replay]]:
    """:func:`replay` for each light, the polygons' facing flags computed from their representative faces'
    ``p0`` and normals ``nrm`` as :func:`.adjacency.facing_flags` computes them: (flags, ties, Replay) per
    light, the lights spread over numba's thread count of threads (each light's replay is sequential)."""
    start, side_key, init = _replay_input(start, side_key, n_keys, initial)
    args = (start, side_key, np.ascontiguousarray(p0, dtype=np.float64), np.ascontiguousarray(nrm, dtype=np.float64))

    def one(light: Light) -> tuple[np.ndarray, int, Replay]:
        src = np.asarray(light.vector, dtype=np.float64)
        flags, ties, *r = _facing_replay(*args, src, light.is_directional, int(n_keys), init)
        return flags, int(ties), Replay(r[0], *(int(x) for x in r[1:]))

    return on_threads(one, lights)


@njit(cache=True)
def _plain_array_s(start, side_from, side_to, facing, V):  # pragma: no cover - compiled
    """TA's array S over the sides of the light-facing faces (or polygons), uncounted; the live keys ``a V + b``."""
    S = np.empty(side_from.size, dtype=np.int64)
    n = 0
    for p in range(start.size - 1):
        if not facing[p]:
            continue
        for q in range(start[p], start[p + 1]):
            a, b = side_from[q], side_to[q]
            rev = b * V + a
            pos = -1
            for i in range(n):
                if S[i] == rev:
                    pos = i
                    break
            if pos >= 0:
                for i in range(pos, n - 1):
                    S[i] = S[i + 1]
                n -= 1
            else:
                S[n] = a * V + b
                n += 1
    return S[:n]


def plain_array_s(
    mesh: Mesh, start: np.ndarray, side_from: np.ndarray, side_to: np.ndarray, facing: np.ndarray
) -> np.ndarray:
    """Run S as printed, compiled and uncounted: each side of a light-facing polygon searches S linearly from
    the front and deletes its reverse (shifting the tail) or appends itself; ascending ids of the edges left."""
    keys = _plain_array_s(start, side_from, side_to, facing, np.int64(mesh.n_vertices))
    return np.unique(packed_edges(mesh, keys)[0])


def directed_keys(side_edge: np.ndarray, side_from: np.ndarray, side_to: np.ndarray) -> np.ndarray:
    """``2 * edge + (from > to)``: the directed key of each side; its reverse is ``key ^ 1``."""
    return 2 * np.asarray(side_edge, dtype=np.int64) + (np.asarray(side_from) > np.asarray(side_to))


_PER_MESH: "weakref.WeakKeyDictionary[Mesh, dict[str, np.ndarray]]" = weakref.WeakKeyDictionary()


def _per_mesh(mesh: Mesh) -> dict[str, np.ndarray]:
    """Light-independent keys of the mesh (cached with it, shared: never written to): every side's
    :func:`directed_keys` and every edge's packed key ``lower * V + higher``, ascending as the edges are."""
    got = _PER_MESH.get(mesh)
    if got is None:
        V = np.int64(mesh.n_vertices)
        got = {
            "side_keys": directed_keys(mesh.side_edge, mesh.side_from, mesh.side_to),
            "edge_keys": mesh.edges[:, 0] * V + mesh.edges[:, 1],
        }
        _PER_MESH[mesh] = got
    return got


def side_keys(mesh: Mesh) -> np.ndarray:
    """:func:`directed_keys` of every side of the mesh (light-independent: cached with the mesh)."""
    return _per_mesh(mesh)["side_keys"]


def packed_edges(mesh: Mesh, keys: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Edge ids and (k, 2) directed (from, to) pairs of packed keys ``from * V + to``, in their order."""
    V = mesh.n_vertices
    pairs = np.stack([keys // V, keys % V], axis=1)
    lo, hi = pairs.min(axis=1), pairs.max(axis=1)
    return np.searchsorted(_per_mesh(mesh)["edge_keys"], lo * V + hi), pairs


@njit(cache=True)
def _keys_to_directed(edges, keys):  # pragma: no cover - compiled
    ids = np.empty(keys.size, dtype=np.int64)
    pairs = np.empty((keys.size, 2), dtype=edges.dtype)
    for i in range(keys.size):
        e = keys[i] >> 1
        ids[i] = e
        flip = keys[i] & 1
        pairs[i, 0] = edges[e, flip]
        pairs[i, 1] = edges[e, 1 - flip]
    return ids, pairs


def keys_to_directed(edges: np.ndarray, keys: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Edge ids and (k, 2) directed vertex pairs of directed keys (key ``2 e + 1``: edge ``e`` reversed)."""
    return _keys_to_directed(np.ascontiguousarray(edges), np.ascontiguousarray(keys, dtype=np.int64))


def first_orientation(ids: np.ndarray, pairs: np.ndarray, unique_ids: np.ndarray) -> np.ndarray:
    """For each of ``unique_ids`` (ascending), the direction of its first entry in S."""
    order = np.lexsort((np.arange(ids.size), ids))
    sorted_ids = ids[order]
    first = order[np.searchsorted(sorted_ids, unique_ids)]
    return pairs[first]


__all__ = [
    "CountedEdgeArray",
    "Replay",
    "replay",
    "replay_many",
    "plain_array_s",
    "popcount",
    "directed_keys",
    "side_keys",
    "packed_edges",
    "keys_to_directed",
    "first_orientation",
]
