"""The shadow-rendering claims: volumes and their stencil steps, the shadow matrix, the lighting terms, culling.

Expected verdicts are recomputed by hand from the paper text (the sums in the comments), not read back
from silcount's own output.  The claims are the ``all_claims`` and ``by_key`` fixtures (``conftest.py``).
"""

from __future__ import annotations

import math

from silcount.papers.claims import AMBIGUOUS, FAILS


def test_depth_subtraction_is_not_a_shadow_volume(by_key):
    """(9) 'Subtraction of these two depth values provides shadow volume' (EESD, stencil paper): the volume is
    extruded geometry counted in the stencil; with depth writes off in pass 2 there is one depth per pixel."""
    for key in ("eesd-depth-subtraction", "stencil-depth-subtraction"):
        c = by_key[key]
        assert c.verdict == FAILS and "one value per pixel" in c.reason, key


def test_ambient_term_defined_by_itself(by_key):
    """(10) 'I_a = K_a I_a' holds only for K_a = 1 or I_a = 0."""
    c = by_key["stencil-ambient-self-definition"]
    assert c.verdict == FAILS and "K_a = 1" in c.rederived and "I_a = 0" in c.rederived
    assert "defined by itself" in c.reason


def test_stencil_step_sums_index_and_bounds(by_key):
    """(11) EESD's inner sum runs j = 1..NP, NP 'the number of polygon', where pixels are meant; the stencil
    paper's inner sum reuses the outer index i (and runs to an undefined NP')."""
    eesd = by_key["eesd-step-sum-bounds"]
    assert eesd.verdict == FAILS and "j = 1..NP" in eesd.rederived and "per pixel" in eesd.reason
    assert "reuses" not in eesd.reason
    st = by_key["stencil-step-sum-index"]
    assert st.verdict == FAILS and "reuses the outer index i" in st.reason and "NP'" in st.rederived


def test_the_shadow_matrix_is_drawn_or_clipped_by_the_normal_it_is_given(by_key):
    """The printed matrix's last row is (N, -D), with D = N.L where it is exact: w = N.P - N.L.  Light (0, 5, 0),
    floor y = 0, occluder point (0.3, 2, 0.1): w = 2 - 5 = -3 with N up (towards the light), clipped by a
    perspective projection; with N down, w = -2 + 5 = 3, drawn.  The paper does not orient N."""
    c = by_key["stencil-shadow-matrix"]
    gl = {r.reading.split(", ")[-1]: r for r in c.readings if "OpenGL" in r.reading}
    assert gl["the plane's normal N facing the light"].holds is False and "w = N.P - N.L = -3" in str(gl)
    assert gl["N facing away from the light"].holds is True and "= 3 for" in gl["N facing away from the light"].outcome
    assert c.verdict == AMBIGUOUS


def test_a_truncated_volume_keeps_the_shadows_of_receivers_before_the_clipping_plane(by_key):
    c = by_key["stencil-truncated-volume"]
    assert [r.holds for r in c.readings] == [True, True, False] and "beyond" in c.readings[2].reading
    assert c.verdict == AMBIGUOUS and "Fig. 7" in c.table_reading


def test_culling_the_faces_turned_from_the_light_culls_faces_the_eye_sees(by_key):
    # by hand: a cube lit from the (+, +, +) octant has its +x, +y, +z faces lit; an eye in the opposite octant
    # sees the -x, -y, -z faces, every one of them turned from the light
    c = by_key["hsd-cull-away-from-light"]
    assert c.verdict == FAILS
    assert "quad_cube, eye opposite the light: 3 of 3 faces turned to the eye are culled" in c.rederived
    assert "quad_cube, eye at the light: 0 of 3" in c.rederived


def test_the_printed_specular_term_is_blinns_not_phongs(by_key):
    # by hand: the eye along N and the light 40 degrees off it: R.V = cos 40 degrees, and H halves the angle
    # between L and V, so N.H = cos 20 degrees; at the mirror direction both terms are 1
    c = by_key["stencil-phong-specular"]
    phong, blinn = math.cos(math.radians(40)) ** 10, math.cos(math.radians(20)) ** 10
    assert c.verdict == FAILS and "Blinn" in c.reason
    assert f"eye along N: (R.V)^n = {phong:.4f}, (N.H)^n = {blinn:.4f}" in c.rederived
    assert "(R.V)^n = 1.0000, (N.H)^n = 1.0000" in c.rederived


def test_the_eesd_pseudocode_and_its_zfail_are_judged(by_key):
    # adding the edge for every face its ray misses adds every edge of the icosahedron (a ray from the light
    # misses most of its 20 faces) and of the torus: 30 and 864 edges
    assert by_key["eesd-pseudocode"].verdict == FAILS
    assert "icosahedron: 30 edges vs 7 silhouette edges" in by_key["eesd-pseudocode"].measured
    assert "torus: 864 edges" in by_key["eesd-pseudocode"].measured
    assert by_key["eesd-step4"].follows_from == "eesd-pseudocode"
    z = by_key["eesd-zfail-like-zpass"]
    assert z.verdict == FAILS and "no caps" in z.measured and "capped volumes 0.0" in z.measured
    for key in ("eesd-step2-lit-pass", "stencil-step2-lit-pass", "stencil-zfail-like-zpass"):
        assert by_key[key].verdict == FAILS
    assert by_key["stencil-zfail-like-zpass"].measured == z.measured  # the same experiment
