"""Benchmark of the 3-D sight test: the numpy engine (planner.coverage.rays) against Embree and Open3D.

Usage: python scripts/bench/bench_rays.py [--n 100000 1000000] [--other-python /tmp/rayvenv/bin/python]
                                          [--engines numpy numpy-1mm embree open3d] [--out FILE.md]

The other engines are not dependencies of the planner: ``--other-python`` is a throwaway environment holding
them (``python -m venv /tmp/rayvenv && /tmp/rayvenv/bin/pip install numpy trimesh embreex open3d``).

Protocol. One scene, made here with the planner: a 60 m x 60 m hall, walls 3 m, with 80 octagonal columns
(0.8 m across, 3 m) and 24 partitions (6 m x 0.2 m, 2.5 m), meshed by ``site_mesh``: 2,008 triangles. The
segments run from stations at 1.5 m (uniform in the hall, 0.3 m or more from any obstacle) to points drawn
uniformly on uniformly drawn triangles, skipping that triangle's wall (an end on an obstacle skips nothing: a
source is a whole obstacle, whose far side must still hide its near one); the first N of 1e6 are used. Each
(engine, N) runs in a fresh process pinned to one core (``taskset -c 0``, Open3D also told ``nthreads=1``) under
``/usr/bin/time -v``: the index build and the query are timed apart, the peak RSS is the whole process's
(imports included; ``import`` alone is measured as N = 0). Embree (embreex) and Open3D (which runs Embree
too) cast float32 rays o + t (e - o), t in [0, 1]; they have no per-ray skip, so their rays stop
``ENGINE_SHORTEN_M`` (1 mm) before the end, clear of the end's own triangle. "differ" counts their verdicts that
differ from the numpy engine's on those same rays (``numpy-1mm``: float64, own surface skipped, shortened 1 mm);
``numpy`` is the planner's call (ends shortened 1e-5 m, own surface skipped).
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from _timed import peak_rss_mb

SCRIPT = Path(__file__).resolve()
#: the other engines' rays stop this far before their ends: they cannot skip the end's own surface per ray
ENGINE_SHORTEN_M = 1e-3


def make_scene(path: Path, n: int, seed: int = 46) -> int:
    """Write the hall's mesh and ``n`` segments to ``path`` (npz); returns the number of triangles."""
    import shapely

    from planner.coverage.mesh import KIND_WALL, site_mesh
    from planner.coverage.rays import NO_SKIP, shortened_ends
    from planner.site import ScanSide, Site, Zone
    from planner.site.model import Obstacle

    rng = np.random.default_rng(seed)
    obstacles = []
    ang = np.pi / 8 + np.arange(8) * np.pi / 4
    for k in range(80):
        cx, cy = 3.0 + 6.0 * (k % 10) + 0.5, 3.0 + 6.0 * (k // 10) + 6.5
        obstacles.append(Obstacle(f"c{k}", tuple(zip(cx + 0.4 * np.cos(ang), cy + 0.4 * np.sin(ang))), 3.0))
    for k in range(24):
        x0, y0 = 2.0 + 9.0 * (k % 6), 1.5 + 14.0 * (k // 6)
        obstacles.append(Obstacle(f"p{k}", ((x0, y0), (x0 + 6, y0), (x0 + 6, y0 + 0.2), (x0, y0 + 0.2)), 2.5))
    hall = Zone("hall", ScanSide.INSIDE, ((0, 0), (60, 0), (60, 60), (0, 60)), (3.0,) * 4)
    mesh = site_mesh(Site("hall", (hall,), obstacles=tuple(obstacles)))
    keep_out = shapely.union_all([shapely.Polygon(o.vertices) for o in obstacles]).buffer(0.3)
    xy = rng.uniform(0.1, 59.9, (3 * n, 2))
    xy = xy[~shapely.contains_xy(keep_out, xy[:, 0], xy[:, 1])][:n]
    origins = np.column_stack([xy, np.full(n, 1.5)])
    tri = rng.integers(0, len(mesh), n)
    u = rng.uniform(size=(n, 2))
    u = np.where(u.sum(axis=1, keepdims=True) > 1, 1 - u, u)
    c = mesh.corners()[tri]
    ends = c[:, 0] + u[:, :1] * (c[:, 1] - c[:, 0]) + u[:, 1:] * (c[:, 2] - c[:, 0])
    np.savez(
        path,
        vertices=mesh.vertices,
        triangles=mesh.triangles,
        source=mesh.source,
        kind=mesh.kind,
        origins=origins,
        ends=ends,
        short_ends=shortened_ends(origins, ends, ENGINE_SHORTEN_M),
        skip=np.where(mesh.kind[tri] == KIND_WALL, mesh.source[tri], NO_SKIP),
    )
    return len(mesh)


def child(engine: str, scene: Path, n: int, out: Path, verdicts: Path) -> None:
    """Build the engine's index and answer the first ``n`` segments; write timings (json) and verdicts (npy)."""
    d = np.load(scene)
    o, e, skip = d["origins"][:n], d["ends"][:n], d["skip"][:n]
    row: dict = {"engine": engine, "n": n, "triangles": len(d["triangles"])}
    t0 = time.perf_counter()
    if engine.startswith("numpy"):
        from planner.coverage.mesh import SiteMesh
        from planner.coverage.rays import occluded, ray_index

        mesh = SiteMesh(d["vertices"], d["triangles"], d["source"], d["kind"])
        ray_index(mesh)
        t1 = time.perf_counter()
        if engine == "numpy":  # the planner's call
            hit = occluded(mesh, o, e, skip) if n else np.zeros(0, bool)
        else:  # the other engines' rays
            hit = occluded(mesh, o, d["short_ends"][:n], skip, shorten_m=0.0) if n else np.zeros(0, bool)
    else:
        v32, f32 = d["vertices"].astype(np.float32), d["triangles"].astype(np.int32)
        o32 = o.astype(np.float32)
        d32 = (d["short_ends"][:n] - o).astype(np.float32)
        if engine == "embree":
            from embreex import rtcore_scene
            from embreex.mesh_construction import TriangleMesh

            scene_ = rtcore_scene.EmbreeScene()
            TriangleMesh(scene_, v32, f32)
            t1 = time.perf_counter()
            hit = scene_.run(o32, d32, dists=np.ones(n, np.float32), query="OCCLUDED") >= 0 if n else np.zeros(0, bool)
        else:
            import open3d as o3d

            scene_ = o3d.t.geometry.RaycastingScene()
            scene_.add_triangles(o3d.core.Tensor(v32), o3d.core.Tensor(f32.astype(np.uint32)))
            t1 = time.perf_counter()
            rays = o3d.core.Tensor(np.concatenate([o32, d32], axis=1))
            hit = scene_.test_occlusions(rays, tfar=1.0, nthreads=1).numpy().astype(bool) if n else np.zeros(0, bool)
    t2 = time.perf_counter()
    row |= {"build_s": t1 - t0, "query_s": t2 - t1, "blocked": int(np.sum(hit))}
    np.save(verdicts, np.asarray(hit, bool))
    out.write_text(json.dumps(row))


def run(python: str, engine: str, scene: Path, n: int, tmp: Path) -> dict:
    """One child under taskset and /usr/bin/time -v; its row with peak_rss_mb and its verdicts."""
    out, ver = tmp / f"{engine}-{n}.json", tmp / f"{engine}-{n}.npy"
    cmd = ["taskset", "-c", "0", "/usr/bin/time", "-v", python, str(SCRIPT), "--child", engine, "--scene", str(scene)]
    proc = subprocess.run(
        [*cmd, "--n", str(n), "--json", str(out), "--verdicts", str(ver)], capture_output=True, text=True
    )
    if proc.returncode != 0:
        raise SystemExit(f"{engine} n={n} failed:\n{proc.stderr[-3000:]}")
    row = json.loads(out.read_text()) | {"peak_rss_mb": peak_rss_mb(proc.stderr)}
    row["verdicts"] = np.load(ver)
    return row


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--n", type=int, nargs="+", default=[100_000, 1_000_000])
    ap.add_argument("--engines", nargs="+", default=["numpy", "numpy-1mm", "embree", "open3d"])
    ap.add_argument("--other-python", default="/tmp/rayvenv/bin/python")
    ap.add_argument("--out", type=Path)
    ap.add_argument("--child")
    ap.add_argument("--scene", type=Path)
    ap.add_argument("--json", type=Path)
    ap.add_argument("--verdicts", type=Path)
    args = ap.parse_args()
    if args.child:
        child(args.child, args.scene, args.n[0], args.json, args.verdicts)
        return
    with tempfile.TemporaryDirectory() as t:
        tmp = Path(t)
        scene = tmp / "scene.npz"
        tris = make_scene(scene, max(args.n))
        lines = [
            f"Scene: {tris} triangles; one core (taskset -c 0); peak RSS of the whole process.",
            "",
            "| engine | segments | build s | query s | segments/s | blocked | differ from numpy | peak RSS MB |",
            "|---|---:|---:|---:|---:|---:|---:|---:|",
        ]
        for n in [0, *args.n]:
            base = None
            for engine in args.engines:
                row = run(sys.executable if engine.startswith("numpy") else args.other_python, engine, scene, n, tmp)
                base = row["verdicts"] if engine == "numpy-1mm" else base
                differ = "" if base is None or engine.startswith("numpy") else str(int(np.sum(base != row["verdicts"])))
                rate = f"{n / row['query_s']:,.0f}" if n else ""
                lines.append(
                    f"| {engine} | {n:,} | {row['build_s']:.3f} | {row['query_s']:.2f} | {rate} | {row['blocked']:,}"
                    f" | {differ} | {row['peak_rss_mb']} |"
                )
                print(lines[-1], flush=True)
    text = "\n".join(lines) + "\n"
    print(text)
    if args.out:
        args.out.write_text(text)


if __name__ == "__main__":
    main()
