"""``silcount audit``: every detector on one mesh, both cost models, cycles, the printed formula.

| module      | what it holds                                           |
|-------------|---------------------------------------------------------|
| compute.py  | :func:`run_audit`: the audit document (schema silcount-audit/1) |
| costs.py    | cycle-weighted totals and the printed formula at the mesh's n, m |
| layout.py   | the document as text, Markdown or JSON                  |
"""
