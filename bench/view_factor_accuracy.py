#!/usr/bin/env python3
"""Helper of bench/view_factor_accuracy.sh: view-factor accuracy of saved form factors.

  view_factor_accuracy.py cube-scene N FILE.h5
      writes the closed unit cube, each face cut into N x N squares (two triangles each, one
      source face per square, normals in), as a scene file (docs/scene-format.md).
  view_factor_accuracy.py cube-check
      checks the exact square-to-square view factors against the closed forms of
      tests/analytic_view_factors.h (Howell C-11, C-14) and the cube's row sums (exactly 1).
  view_factor_accuracy.py city CSV LABEL REF.h5[,REF2.h5...] RUN.h5...
      appends to CSV one row per RUN (solved with --save-formfactors on builtin:city with the
      scene's own triangles as patches), against the reference (the mean of the REF files,
      high-effort runs with other seeds): rays, ranks, threads, form-factor wall time, and
        rowsum_rms       RMS over patches (plain, one patch one vote) of sum_j F_ij - reference
        rowsum_rms_area  the same, area-weighted
        group_rms_rel    RMS relative error of the building-to-building group factors
                         F(a->b) = sum_{i in a} A_i sum_{j in b} F_ij / A_a, over the ordered
                         pairs of distinct buildings with reference F(a->b) > GROUP_FLOOR (1e-3)
        group_rms_abs    RMS absolute error over the same pairs
      each also "_corr": with the reference's own noise taken out (measured^2 - noise^2, the
      noise of the mean of the REF files estimated from their spread; empty with one REF).
  view_factor_accuracy.py cube CSV LABEL N RUN.h5...
      the same for the cube against the exact factors: mean and RMS absolute error of the
      square-to-square factors F(a->b) over the ordered pairs of squares on different faces
      (same-face pairs are 0 in both), and the row-sum errors against 1.
  view_factor_accuracy.py cube-groups-scene N FILE.obj
      the same cube as an OBJ (+ .mtl beside it) with one group per square, so that the result's
      /groups are the square-to-square factors whatever F's rows are stored as.
  view_factor_accuracy.py cube-groups CSV LABEL N RUN.h5...
      the square-pair factors of such runs' /groups against the exact ones: mean absolute error,
      mean relative error, largest relative error (exact rows stored once a pair, which write
      no /formfactors, against whole rows).
  view_factor_accuracy.py fit CSV LABEL COLUMN TARGET
      least-squares slope of log COLUMN against log rays for the rows of LABEL, and the rays
      (and form-factor time, scaled linearly in rays from the largest run) at which the fit
      reaches TARGET.
Needs h5py and NumPy (Debian's python3-h5py, python3-numpy).
"""
import csv
import math
import os
import re
import sys

import h5py
import numpy as np

from csv_rows import append_row

GROUP_FLOOR = float(os.environ.get("GROUP_FLOOR", "1e-3"))


# ---------------------------------------------------------------- exact factors, the cube
def _phi(u, d2):
    """Second primitive in u of (1/2) ln(u^2 + d^2), constants dropped."""
    r2 = u * u + d2
    d = np.sqrt(d2)
    with np.errstate(divide="ignore", invalid="ignore"):
        log_term = np.where(r2 > 0, 0.25 * (u * u - d2) * np.log(np.where(r2 > 0, r2, 1)), 0)
        atan_term = np.where(d > 0, d * u * np.arctan(u / np.where(d > 0, d, 1)), 0)
    return log_term - 0.75 * u * u + atan_term


def _edges(lo, hi, normal_axis, inward):
    """The four edges of an axis-aligned rectangle [lo, hi] (hi - lo zero along normal_axis),
    counter-clockwise seen from the side `inward` (+1/-1 along normal_axis) points to:
    a list of (axis, base point [..., 3], start, end) with the edge running start -> end
    along axis (end < start where it runs backwards)."""
    a, b = [k for k in range(3) if k != normal_axis]
    # (a, b, normal) right-handed? Counter-clockwise around +normal_axis is a -> b if so.
    right = (a + 1) % 3 == b
    ccw = right == (inward > 0)
    # corners in the (a, b) plane, counter-clockwise around +a x +b
    ca = [lo[..., a], hi[..., a], hi[..., a], lo[..., a]]
    cb = [lo[..., b], lo[..., b], hi[..., b], hi[..., b]]
    order = [0, 1, 2, 3] if ccw else [0, 3, 2, 1]
    edges = []
    for k in range(4):
        p, q = order[k], order[(k + 1) % 4]
        base = np.array(lo, dtype=float, copy=True)
        if (p, q) in ((0, 1), (2, 3), (1, 0), (3, 2)):  # runs along a at fixed b
            base[..., b] = cb[p]
            edges.append((a, base, ca[p], ca[q]))
        else:  # runs along b at fixed a
            base[..., a] = ca[p]
            edges.append((b, base, cb[p], cb[q]))
    return edges


def rect_factor(lo1, hi1, axis1, in1, lo2, hi2, axis2, in2):
    """Exact F(1 -> 2) between axis-aligned rectangles (arrays broadcast), by Stokes:
    A1 F12 = 1/(2 pi) sum over pairs of parallel edges of +-int int ln r."""
    total = 0.0
    for ax1, base1, s1, e1 in _edges(lo1, hi1, axis1, in1):
        for ax2, base2, s2, e2 in _edges(lo2, hi2, axis2, in2):
            if ax1 != ax2:
                continue
            diff = base1 - base2
            d2 = sum(diff[..., k] ** 2 for k in range(3) if k != ax1)
            # int_{s1}^{e1} int_{s2}^{e2} f(y - eta): orientation carried by the limits
            total = total + (_phi(e1 - s2, d2) - _phi(s1 - s2, d2) - _phi(e1 - e2, d2)
                             + _phi(s1 - e2, d2))
    area1 = np.prod([hi1[..., k] - lo1[..., k] for k in range(3) if k != axis1], axis=0)
    return total / (2 * math.pi * area1)


def cube_squares(n):
    """The 6 n^2 squares of the unit cube: lo, hi [m,3], normal axis, inward sign, per square,
    in source-face order (face f = 2*axis + side, then i, j)."""
    lo, hi, axis, inward = [], [], [], []
    for ax in range(3):
        for side in (0, 1):
            a, b = [k for k in range(3) if k != ax]
            for i in range(n):
                for j in range(n):
                    l = np.zeros(3)
                    h = np.zeros(3)
                    l[ax] = h[ax] = side
                    l[a], h[a] = i / n, (i + 1) / n
                    l[b], h[b] = j / n, (j + 1) / n
                    lo.append(l)
                    hi.append(h)
                    axis.append(ax)
                    inward.append(1 if side == 0 else -1)
    return np.array(lo), np.array(hi), np.array(axis), np.array(inward)


def cube_exact(n):
    """Exact F between the squares, [6n^2, 6n^2]."""
    lo, hi, axis, inward = cube_squares(n)
    m = len(lo)
    per = n * n
    f = np.zeros((m, m))
    for f1 in range(6):
        r1 = slice(f1 * per, (f1 + 1) * per)
        for f2 in range(6):
            if f1 == f2:
                continue
            r2 = slice(f2 * per, (f2 + 1) * per)
            f[r1, r2] = rect_factor(lo[r1, None, :], hi[r1, None, :], f1 // 2, inward[r1][0],
                                    lo[None, r2, :], hi[None, r2, :], f2 // 2, inward[r2][0])
    return f


def square_corners(lo, hi, axis, inward, s):
    """Square s's four corners, counter-clockwise seen from inside the cube."""
    ax = axis[s]
    a, b = [k for k in range(3) if k != ax]
    corners = []
    for ca, cb in ((0, 0), (1, 0), (1, 1), (0, 1)):
        v = lo[s].copy()
        v[a] = hi[s][a] if ca else lo[s][a]
        v[b] = hi[s][b] if cb else lo[s][b]
        corners.append(v)
    # (v1 - v0) x (v2 - v0) points along +ax if (a, b, ax) is right-handed
    if ((a + 1) % 3 == b) != (inward[s] > 0):
        corners = corners[::-1]
    return corners


def write_cube_scene(n, path):
    lo, hi, axis, inward = cube_squares(n)
    vertices, triangles = [], []
    for s in range(len(lo)):
        corners = square_corners(lo, hi, axis, inward, s)
        k = len(vertices)
        vertices.extend(corners)
        triangles.append([k, k + 1, k + 2])
        triangles.append([k, k + 2, k + 3])
    nt = len(triangles)
    with h5py.File(path, "w") as f:
        # fixed-length strings: the reader refuses h5py's variable-length root attributes
        f.attrs["kind"] = np.bytes_("radiosity scene")
        f.attrs["format_version"] = np.int32(1)
        f.attrs["length_unit"] = np.bytes_("m")
        f["mesh/vertices"] = np.asarray(vertices, dtype=np.float64)
        f["mesh/triangles"] = np.asarray(triangles, dtype=np.int64)
        # material 0 reflects, material 1 (square 0 only) also emits, so that there is a solve
        material = np.zeros(nt, dtype=np.int32)
        material[:2] = 1
        f["mesh/material"] = material
        f["mesh/source_face"] = np.repeat(np.arange(len(lo), dtype=np.int64), 2)
        f["materials/reflectance"] = np.full((2, 3), 0.5)
        f["materials/emission"] = np.array([[0.0] * 3, [1.0] * 3])


def cube_check():
    from math import atan, log, pi, sqrt
    def parallel(a, b, c):  # Howell C-11
        X, Y = a / c, b / c
        x2, y2 = 1 + X * X, 1 + Y * Y
        return 2 / (pi * X * Y) * (log(sqrt(x2 * y2 / (x2 + Y * Y))) + X * sqrt(y2) * atan(X / sqrt(y2))
                                   + Y * sqrt(x2) * atan(Y / sqrt(x2)) - X * atan(X) - Y * atan(Y))
    def perpendicular(l, h, w2):  # Howell C-14
        H, W = h / l, w2 / l
        H2, W2 = H * H, W * W
        S = sqrt(H2 + W2)
        t1 = W * atan(1 / W) + H * atan(1 / H) - S * atan(1 / S)
        a = (1 + W2) * (1 + H2) / (1 + W2 + H2)
        b = W2 * (1 + W2 + H2) / ((1 + W2) * (W2 + H2))
        c = H2 * (1 + H2 + W2) / ((1 + H2) * (H2 + W2))
        return (t1 + 0.25 * log(a * b ** W2 * c ** H2)) / (pi * H)
    A = np.array
    got = rect_factor(A([0, 0, 0.]), A([2, 3, 0.]), 2, 1, A([0, 0, 1.5]), A([2, 3, 1.5]), 2, -1)
    want = parallel(2, 3, 1.5)
    print(f"parallel 2x3 at 1.5: {got:.12f} exact {want:.12f}")
    assert abs(got - want) < 1e-12
    # h-rectangle in plane y=0 (x in [0,l], z in [0,h], facing +y), w2-rectangle on the floor
    # z=0 (x in [0,l], y in [0,w2], facing +z), sharing the edge x in [0,l]
    got = rect_factor(A([0, 0, 0.]), A([1.7, 0, 0.6]), 1, 1, A([0, 0, 0.]), A([1.7, 2.2, 0]), 2, 1)
    want = perpendicular(1.7, 0.6, 2.2)
    print(f"perpendicular l=1.7 h=0.6 w=2.2: {got:.12f} exact {want:.12f}")
    assert abs(got - want) < 1e-12
    for n in (1, 3, 8):
        f = cube_exact(n)
        rows = f.sum(axis=1)
        print(f"cube N={n}: row sums within {np.abs(rows - 1).max():.2e} of 1, min F {f.min():.3e}")
        assert np.abs(rows - 1).max() < 1e-9 and f.min() >= -1e-15
    f1 = cube_exact(1)
    print(f"cube N=1: opposite {f1[0, 1]:.6f} (0.199825), adjacent {f1[0, 2]:.6f} (0.200044)")


# ---------------------------------------------------------------- reading results
def load(path):
    with h5py.File(path, "r") as f:
        start = f["formfactors/row_start"][:]
        col = f["formfactors/column"][:]
        val = f["formfactors/value"][:]
        area = f["patches/area"][:]
        face = f["patches/source_face"][:]
        attrs = dict(f.attrs)
        groups = f["groups/view_factors"][:] if "groups/view_factors" in f else None
        names = [n.decode() if isinstance(n, bytes) else str(n)
                 for n in f["groups/view_factors"].attrs["names"]] if groups is not None else []
    row = np.repeat(np.arange(len(start) - 1), np.diff(start))
    return dict(row=row, col=col, val=val, area=area, face=face, attrs=attrs, groups=groups,
                names=names)


def city_groups(r, group, ng):
    """The building-to-building factors: the program's /groups (each combined with its
    reciprocal estimate; labels ground, building 1, ...) where the file has them, else summed
    from F's rows."""
    if r["groups"] is not None and len(r["names"]) == ng and r["names"][0] == "ground":
        return r["groups"]
    return group_factors(r, group, ng)


def attr(r, name, default=""):
    v = r["attrs"].get(name, default)
    return v.decode() if isinstance(v, bytes) else v


def option(r, name):
    for line in str(attr(r, "options")).splitlines():
        k, _, v = line.partition("=")
        if k.strip() == name:
            return v.strip()
    return ""


def row_sums(r):
    return np.bincount(r["row"], weights=r["val"], minlength=len(r["area"]))


def group_factors(r, group, ngroups):
    """F(a -> b) = sum_{i in a} A_i sum_{j in b} F_ij / A_a, [ngroups, ngroups]."""
    g_row, g_col = group[r["row"]], group[r["col"]]
    flux = np.bincount(g_row * ngroups + g_col, weights=r["area"][r["row"]] * r["val"],
                       minlength=ngroups * ngroups).reshape(ngroups, ngroups)
    a = np.bincount(group, weights=r["area"], minlength=ngroups)
    return flux / a[:, None]


def rms(x, w=None):
    return math.sqrt(np.average(np.square(x), weights=w))


def corrected(measured, noise):
    return math.sqrt(max(measured ** 2 - noise ** 2, 0.0))


def run_fields(label, r):
    rays = int(attr(r, "rays_per_patch"))
    ranks = int(attr(r, "ranks"))
    threads = int(option(r, "threads") or 1)
    t = float(attr(r, "time_formfactors"))
    return dict(label=label, patches=len(r["area"]), rays=rays, seed=attr(r, "seed"),
                ranks=ranks, threads=threads, ff_seconds=f"{t:.3f}",
                cpu_seconds=f"{t * ranks * threads:.3f}",
                rays_per_cpu_second=f"{rays * len(r['area']) / (t * ranks * threads):.4g}")


def city(csv_path, label, refs, runs):
    refs = [load(p) for p in refs.split(",")]
    area, face = refs[0]["area"], refs[0]["face"]
    group = (face + 4) // 5  # 0 ground, k building k
    ng = int(group.max()) + 1
    ref_rows = np.array([row_sums(r) for r in refs])
    ref_groups = np.array([city_groups(r, group, ng) for r in refs])
    rs_ref, g_ref = ref_rows.mean(axis=0), ref_groups.mean(axis=0)
    n_ref = len(refs)
    ref_rays = sum(int(attr(r, "rays_per_patch")) for r in refs)
    b = np.arange(1, ng)
    pairs = np.array([(i, j) for i in b for j in b if i != j and g_ref[i, j] > GROUP_FLOOR])
    gi, gj = pairs[:, 0], pairs[:, 1]
    gref = g_ref[gi, gj]
    # The reference's own noise, from the spread of the REF files about their mean (the
    # estimator is quasi-Monte Carlo, scrambled Sobol', so no binomial formula holds): the
    # variance of one file (unbiased over the n files) over n, the variance of the mean.
    nan = float("nan")
    rs_noise = rs_noise_area = g_noise_rel = g_noise_abs = nan
    if n_ref > 1:
        var_rows = np.sum((ref_rows - rs_ref) ** 2, axis=0) / (n_ref - 1) / n_ref
        rs_noise = math.sqrt(np.mean(var_rows))
        rs_noise_area = math.sqrt(np.average(var_rows, weights=area))
        var_g = np.sum((ref_groups[:, gi, gj] - gref) ** 2, axis=0) / (n_ref - 1) / n_ref
        g_noise_rel = math.sqrt(np.mean(var_g / gref ** 2))
        g_noise_abs = math.sqrt(np.mean(var_g))
    print(f"{label}: reference {n_ref} file(s), {ref_rays} rays a patch in all; its noise: "
          f"row sums {rs_noise:.3g}, area-weighted {rs_noise_area:.3g}; groups {g_noise_rel:.3g} relative, {g_noise_abs:.3g} "
          f"absolute over {len(pairs)} building pairs with F > {GROUP_FLOOR:g}; mean 1 - row sum "
          f"(sky view factor) {np.mean(1 - rs_ref):.4f}")
    for path in runs:
        r = load(path)
        assert len(r["area"]) == len(area) and np.array_equal(r["face"], face), path
        e = row_sums(r) - rs_ref
        g = city_groups(r, group, ng)[gi, gj]
        row = run_fields(label, r)
        m_rs, m_rsa = rms(e), rms(e, area)
        m_gr, m_ga = rms((g - gref) / gref), rms(g - gref)
        nan = not math.isfinite(g_noise_rel)
        row.update(rowsum_rms=f"{m_rs:.4g}",
                   rowsum_rms_corr="" if nan else f"{corrected(m_rs, rs_noise):.4g}",
                   rowsum_rms_area=f"{m_rsa:.4g}",
                   rowsum_rms_area_corr="" if nan else f"{corrected(m_rsa, rs_noise_area):.4g}",
                   group_rms_rel=f"{m_gr:.4g}",
                   group_rms_rel_corr="" if nan else f"{corrected(m_gr, g_noise_rel):.4g}",
                   group_rms_abs=f"{m_ga:.4g}",
                   group_rms_abs_corr="" if nan else f"{corrected(m_ga, g_noise_abs):.4g}",
                   group_pairs=len(pairs), ref_rays=ref_rays,
                   groups_from="program /groups" if r["groups"] is not None else "F's rows", ref_rowsum_noise=f"{rs_noise:.3g}",
                   ref_group_noise_rel=f"{g_noise_rel:.3g}")
        append_row(csv_path, row)
        print(", ".join(f"{k} {v}" for k, v in row.items()))


def cube(csv_path, label, n, runs):
    exact = cube_exact(n)
    per = n * n
    face_of = np.arange(6 * per) // per
    other = face_of[:, None] != face_of[None, :]
    for path in runs:
        r = load(path)
        squares = r["face"]
        m = int(squares.max()) + 1
        assert m == 6 * per, path
        g = group_factors(r, squares, m)
        err = (g - exact)[other]
        e = row_sums(r) - 1
        sq_rows = g.sum(axis=1) - 1
        row = run_fields(label, r)
        row.update(rows=option(r, "rows") or "sampled", pair_mean_abs=f"{np.mean(np.abs(err)):.4g}", pair_rms=f"{rms(err):.4g}",
                   pair_mean_exact=f"{np.mean(exact[other]):.4g}",
                   pair_mean_rel=f"{np.sum(np.abs(err)) / np.sum(exact[other]):.4g}",
                   rowsum_rms=f"{rms(e):.4g}", rowsum_max=f"{np.abs(e).max():.4g}",
                   square_rowsum_rms=f"{rms(sq_rows):.4g}")
        append_row(csv_path, row)
        print(", ".join(f"{k} {v}" for k, v in row.items()))


def write_cube_groups_scene(n, path):
    lo, hi, axis, inward = cube_squares(n)
    mtl = path[:-4] + ".mtl"
    with open(mtl, "w") as m:  # square 0 also emits, so that there is a solve
        m.write("newmtl white\nKd 0.5 0.5 0.5\nnewmtl lamp\nKd 0.5 0.5 0.5\nKe 1 1 1\n")
    with open(path, "w") as o:
        o.write(f"mtllib {mtl.rsplit('/', 1)[-1]}\n")
        for s in range(len(lo)):
            corners = square_corners(lo, hi, axis, inward, s)
            o.write(f"g square{s:05d}\nusemtl {'lamp' if s == 0 else 'white'}\n")
            for v in corners:
                o.write("v %.17g %.17g %.17g\n" % tuple(v))
            o.write(f"f {4 * s + 1} {4 * s + 2} {4 * s + 3} {4 * s + 4}\n")


def cube_groups(csv_path, label, n, runs):
    exact = cube_exact(n)
    positive = exact > 0
    for path in runs:
        with h5py.File(path, "r") as f:
            table = f["groups/view_factors"]
            names = [x.decode() if isinstance(x, bytes) else x for x in table.attrs["names"]]
            order = [int(re.search(r"square(\d+)", name).group(1)) for name in names]
            g = np.zeros_like(exact)
            g[np.ix_(order, order)] = table[:]
            options = f.attrs["options"]
            options = options.decode() if isinstance(options, bytes) else options
        err = np.abs(g - exact)[positive]
        rows = [line for line in options.splitlines() if line.startswith(("rows", "values"))]
        row = {"label": label, "n": n, "rows": "; ".join(rows),
               "pair_mean_abs": f"{err.mean():.4g}",
               "pair_mean_rel": f"{np.mean(err / exact[positive]):.4g}",
               "pair_max_rel": f"{np.max(err / exact[positive]):.4g}"}
        append_row(csv_path, row)
        print(", ".join(f"{k} {v}" for k, v in row.items()))


def fit(csv_path, label, column, target):
    with open(csv_path) as f:
        rows = [r for r in csv.DictReader(f) if r["label"] == label and r.get(column)]
    rays = np.array([float(r["rays"]) for r in rows])
    err = np.array([float(r[column]) for r in rows])
    ok = err > 0
    slope, icpt = np.polyfit(np.log(rays[ok]), np.log(err[ok]), 1)
    need = math.exp((math.log(target) - icpt) / slope)
    big = rows[int(np.argmax(rays))]
    t = float(big["ff_seconds"]) * need / float(big["rays"])
    print(f"{label} {column}: slope {slope:.3f} over rays {int(rays.min())}..{int(rays.max())}; "
          f"{target:g} at {need:.3g} rays a patch, about {t:.3g} s form factors "
          f"({float(big['ranks']) * float(big['threads']) * t:.3g} CPU s; linear in rays from "
          f"{big['rays']} rays in {big['ff_seconds']} s)")


def main(argv):
    cmd = argv[1]
    if cmd == "cube-scene":
        write_cube_scene(int(argv[2]), argv[3])
    elif cmd == "cube-check":
        cube_check()
    elif cmd == "city":
        city(argv[2], argv[3], argv[4], argv[5:])
    elif cmd == "cube":
        cube(argv[2], argv[3], int(argv[4]), argv[5:])
    elif cmd == "cube-groups-scene":
        write_cube_groups_scene(int(argv[2]), argv[3])
    elif cmd == "cube-groups":
        cube_groups(argv[2], argv[3], int(argv[4]), argv[5:])
    elif cmd == "fit":
        fit(argv[2], argv[3], argv[4], float(argv[5]))
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main(sys.argv)
