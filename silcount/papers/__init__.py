"""The papers, checked: sympy re-derivation, claims, tables, figures, the projection algebra.

| module         | what it holds                                                           |
|----------------|-------------------------------------------------------------------------|
| formulas.py    | the closed forms re-derived from the per-line costs in ``silcount/models/``      |
| growth.py      | measured operation counts against mesh size (the complexity evidence)   |
| witness.py     | meshes and lights reaching a detector's worst-case growth (O() claims)  |
| projection.py  | the stencil paper's planar shadow matrix and "new pixel" formula        |
| claims.py      | every checkable statement with its verdict                              |
| tables.py      | the papers' tables: printed, re-derived, measured                       |
| figures.py     | the papers' charts, printed and corrected; growth plots                 |
| budget.py      | the report's frame budget, and the papers' FPS changes against it       |
"""
