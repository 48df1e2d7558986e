"""Second implementations the tests compare silcount with, outside the package: ``render_baseline`` (the
single-threaded rasteriser of commit 318ab63, bit for bit) and ``gl_stencil`` (the same stencil passes drawn by
OpenGL, through moderngl).  Tests import them as ``oracles.NAME`` (``tests/`` is on pytest's path); the
benchmarks time silcount against them as ``tests.oracles.NAME`` (run from the checkout's root).
"""
