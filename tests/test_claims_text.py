"""The papers' cross-references and citations: section numbers, reference entries, attributions.

Expected verdicts are recomputed by hand from the paper text (the sums in the comments), not read back
from silcount's own output.  The claims are the ``all_claims`` and ``by_key`` fixtures (``conftest.py``).
"""

from __future__ import annotations

from silcount.papers.claims import AMBIGUOUS, FAILS


def test_the_organisation_paragraph_is_itself_in_the_related_works(by_key):
    # it stands after the heading "II. PREVIOUS WORKS", so its "next section" is III, the silhouette's definition
    c = by_key["hsd-organisation-related"]
    assert c.verdict == FAILS and "numbers it 2, not 3" in c.reason


def test_organisation_paragraph_numbers_the_conclusion_wrongly(by_key):
    """Issue 24, 4(1): HSD's organisation paragraph puts the conclusion in 'section 8'; its heading is IX."""
    c = by_key["hsd-organisation-conclusion"]
    assert c.verdict == FAILS and c.family == "cross-reference"
    assert "9" in c.reason and "not 8" in c.reason
    from silcount.papers.claims.citations import roman

    assert [roman(x) for x in ("I", "IV", "VIII", "IX", "XIV")] == [1, 4, 8, 9, 14]


def test_gorman_ratio_cited_as_a_survey(by_key):
    """(3) HSD cites Gorman's ratio as [14], Wang, Tang and Dong's survey."""
    c = by_key["hsd-cite-gorman"]
    assert c.verdict == FAILS and "does not name Gorman" in c.reason and "Wang" in c.rederived


def test_citations_to_unrelated_entries(by_key):
    """(4) HSD [16] motion control; HSD [15, 17] crowd rendering and VR realism for culling (AMBIGUOUS: crowd
    rendering optimisation may treat culling, its title does not say); EESD [19] crowd simulation; EESD [6]."""
    for key, words in (
        ("hsd-cite-16-silhouette", "motion control"),
        ("eesd-cite-19-shadow", "crowd simulation"),
        ("eesd-cite-6-definition", "Code Form Game"),
    ):
        c = by_key[key]
        assert c.verdict == FAILS and c.family == "attribution" and words in c.reason, key
    c = by_key["hsd-cite-culling"]
    assert c.verdict == AMBIGUOUS and [r.holds for r in c.readings] == [False, True] and c.table_reading


def test_attributions_with_no_reference_entry(by_key):
    """(5) EESD's 'Northup and Markosion' and HSD's 'Saito and Takahashi' have no entry in their paper's list."""
    for key, n in (("eesd-northrup-markosian-entry", 22), ("hsd-saito-takahashi-entry", 17)):
        c = by_key[key]
        assert c.verdict == FAILS and "no entry" in c.reason and f"{n} reference entries" in c.rederived, key
