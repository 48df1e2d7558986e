"""Measure `silcount render`'s memory per pixel and set it beside :mod:`silcount.render.memory`'s estimate.

Each (method, resolution) runs in a fresh Python process: the shared scene ``cube_on_floor`` (or
``--scene``) at ``N x N``, rendered and written by the CLI (``--image`` too, for the shaded picture's
row), and ``getrusage(RUSAGE_SELF).ru_maxrss`` is its peak resident memory.  The slope between two
resolutions is the memory per pixel, free of the interpreter's, numba's and the scene's fixed part.
The estimate must be at least the measured slope (it is an upper bound, for every pixel covered); the
ratio says by how much.  ``--full`` scales the scene's first object (the floor) a hundredfold, so that
every pixel is covered, the case the estimate is for.

    python -m benchmarks.render_memory [--sizes 1024,2048] [--scene PATH] [--full]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

from benchmarks.common import ROOT, load_line

CHILD = """
import resource, sys
import silcount.cli.render as cli
from silcount.cli.main import main
from silcount.render.scene import load_scene
scene_path, n, method, out, image = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4], sys.argv[5] == "1"
scene = load_scene(scene_path).with_resolution(n, n)
cli.load_scene = lambda *args: scene
argv = ["render", scene_path, "--method", method, "--out", out, "--max-memory", "1T"]
rc = main(argv + (["--image", out + ".shaded.png"] if image else []))
assert rc == 0, rc
print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024)
"""


def peak(scene: str, n: int, method: str, image: bool, out: str) -> int:
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    args = [sys.executable, "-c", CHILD, scene, str(n), method, out, "1" if image else "0"]
    proc = subprocess.run(args, capture_output=True, text=True, env=env, check=True)
    return int(proc.stdout.strip().splitlines()[-1])


def main() -> None:
    from silcount.render.memory import render_bytes

    default_scene = Path(os.environ.get("SILCOUNT_SCENE_DIR", ROOT.parent / "shared" / "scenes")) / "cube_on_floor.json"
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="1024,2048", help="two square resolutions N1,N2")
    parser.add_argument("--scene", default=str(default_scene))
    parser.add_argument("--full", action="store_true", help="scale the floor so that every pixel is covered")
    args = parser.parse_args()
    n1, n2 = (int(v) for v in args.sizes.split(","))
    print(f"{load_line()}; scene {args.scene}{' (floor x100)' if args.full else ''}; "
          f"{n1}^2 and {n2}^2 pixels")  # fmt: skip
    print(f"{'case':<16} {'measured B/px':>14} {'estimate B/px':>14} {'estimate/measured':>18}")
    with tempfile.TemporaryDirectory() as tmp:
        if args.full:
            doc = json.loads(Path(args.scene).read_text())
            for obj in doc["objects"]:
                obj["mesh"] = str(Path(args.scene).parent / obj["mesh"])
            doc["objects"][0]["scale"] = 100.0
            args.scene = str(Path(tmp) / "full.json")
            Path(args.scene).write_text(json.dumps(doc))
        for method, image in [("zpass", False), ("zfail", False), ("planar", False), ("raycast", False),
                              ("zfail", True), ("raycast", True)]:  # fmt: skip
            out = str(Path(tmp) / f"{method}.png")
            a, b = peak(args.scene, n1, method, image, out), peak(args.scene, n2, method, image, out)
            measured = (b - a) / (n2 * n2 - n1 * n1)
            estimate = render_bytes(1, 1, method, image)
            name = method + (" --image" if image else "")
            print(f"{name:<16} {measured:>14.1f} {estimate:>14d} {estimate / measured:>18.2f}")


if __name__ == "__main__":
    main()
