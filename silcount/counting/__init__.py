"""Counting: what an operation costs, observed or annotated.

| module        | what it holds                                                              |
|---------------|----------------------------------------------------------------------------|
| arithmetic.py | counting numbers and counted memory: every add, mul, cmp, read, write      |
| models.py     | ``silcount/models/`` access and the ``paper`` cost model (steps x annotated costs) |
| cycles.py     | cycle profiles that weigh the kinds (paper, unit, CPU models, measured)    |
"""
