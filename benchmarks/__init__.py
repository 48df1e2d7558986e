"""silcount's benchmarks, one module per subject, run from the checkout's root (as pandas' ``asv_bench``).

    SILCOUNT_MESH_DIR=../shared/data .venv/bin/python -m benchmarks.detectors --rounds 3

| module          | what it times                                                                  |
|-----------------|--------------------------------------------------------------------------------|
| detectors       | every detector on the subdivided bunny: reference floor, many, audit, engines |
| literature      | gaussmap and cones against the reference kernel (``detectors --sections``)     |
| ab_literature   | the same queries in two source trees, interleaved                              |
| corpus          | ``silcount corpus`` on the shared corpus, per worker count                     |
| scaleout_bound  | the corpus sweep's two-worker ceiling, measured inside the workers            |
| render          | the stencil renderer's frames against the 318ab63 rasteriser (and llvmpipe)    |
| render_process  | ``silcount render`` as whole processes, this tree against 318ab63              |
| report          | ``silcount report`` on this tree and a baseline, outputs compared byte for byte |
| classes         | class selection on synthetic series with the corpus's sizes and scatter        |

:mod:`benchmarks.common` holds what they share: the bunny (:func:`~benchmarks.common.build_mesh`), the
lights (:func:`~benchmarks.common.lights`, on :func:`silcount.mesh.lights.random_directions`), the best-of
timer, the memory floor, the load line, and the child process that imports a baseline tree's silcount
(:func:`~benchmarks.common.child_command`, :func:`~benchmarks.common.tree_env`).  The second
implementations timed against silcount are the tests' oracles (``tests/oracles/``).

Adding a benchmark: a module ``benchmarks/NAME.py`` with a docstring (what it measures, how to run it:
``python -m benchmarks.NAME ...``), a ``main()`` under ``if __name__ == "__main__":``, helpers imported from
:mod:`benchmarks.common` (``from benchmarks.common import best_time, load_line``) or a sibling
(``from benchmarks.corpus import one``) rather than copied, a line of the table above, and ratios against a
baseline measured in the same run with the load printed (:func:`~benchmarks.common.load_line`).  A child
process runs ``child_command(__spec__.name, ...)`` with ``env=tree_env(tree)``; nothing edits
``sys.path`` (``tests/test_layout.py`` reads every file here for it, and holds each to 400 lines).
"""
