"""The error of unbiased form-factor estimators from the spread over seeds (issue 16;
docs/notebook/history.md, "Less error per ray in occluded scenes"). The estimator is unbiased,
so the RMS over patches of the standard deviation over seeds of a row sum is its RMS error,
without a reference. Two variants are scored on the same saved rows, so they share the rays:

  spread FILES...          row sums and building-to-building group factors (builtin:city:
                           source faces 5k-4 .. 5k are building k), as sampled and with the
                           two estimates of each pair combined through reciprocity,
                           F~_ij = A_j (F_ij + F_ji) / (A_i + A_j)
  near-field R FILES...    pairs of facing patches (centroids within R) proven unoccluded (no
                           triangle meets the inside of their convex hull: separating planes
                           among i's, j's, the blocker's and edge-cross-edge axes), and the
                           row sums' spread once those pairs' sampled part is replaced by a
                           deterministic value (the spread of the rest of the row)

FILES: results of `solve --save-formfactors --max-area 1e9` of one scene, one per seed
(bench/seed_spread.sh). Needs h5py, NumPy and SciPy.
"""
import math
import sys

import h5py
import numpy as np
import scipy.sparse as sp

from view_factor_accuracy import group_factors, load


def rms(x):
    return math.sqrt(np.mean(np.square(x)))


def matrix(r, n):
    return sp.csr_matrix((r["val"], (r["row"], r["col"])), shape=(n, n))


def reciprocal(f, area):
    m = (f + f.T).tocoo()
    return sp.csr_matrix((m.data * area[m.col] / (area[m.row] + area[m.col]), (m.row, m.col)),
                         shape=f.shape)


def spread(files):
    runs = [load(p) for p in files]
    area, face = runs[0]["area"], runs[0]["face"]
    n = len(area)
    group = (face + 4) // 5
    ng = int(group.max()) + 1
    for name, transform in (("as sampled", lambda f: f), ("reciprocity combined",
                                                          lambda f: reciprocal(f, area))):
        sums, groups = [], []
        for r in runs:
            f = transform(matrix(r, n)).tocoo()
            sums.append(np.bincount(f.row, weights=f.data, minlength=n))
            groups.append(group_factors(dict(row=f.row, col=f.col, val=f.data, area=area), group, ng))
        sums, groups = np.array(sums), np.array(groups)
        mean = groups.mean(axis=0)
        pairs = np.zeros((ng, ng), bool)
        pairs[1:, 1:] = mean[1:, 1:] > 1e-3
        np.fill_diagonal(pairs, False)
        sd = sums.std(axis=0, ddof=1)
        print(f"{name}: row sums {rms(sd):.3e} (ground {rms(sd[group == 0]):.3e}, buildings "
              f"{rms(sd[group > 0]):.3e}); groups {rms(groups.std(axis=0, ddof=1)[pairs] / mean[pairs]):.3%} "
              f"over {pairs.sum()} pairs; {len(runs)} seeds")


def provenUnoccluded(corners, normal, centroid, radius, slack, i, j, distance):
    hull = np.concatenate([corners[i], corners[j]])
    sphere = 0.5 * (centroid[i] + centroid[j])
    reach = 0.5 * distance + radius[i] + radius[j]
    cand = np.nonzero(np.linalg.norm(centroid - sphere, axis=1) <= reach + radius)[0]
    cand = cand[(cand != i) & (cand != j)]
    t = corners[cand]
    apart = np.zeros(len(cand), bool)
    for k in (i, j):  # behind the plane of i or of j, which bound the hull
        apart |= (np.einsum("mvd,d->mv", t - corners[k][0], normal[k]) <= slack).all(axis=1)
    side = hull @ normal[cand].T - np.einsum("md,md->m", t[:, 0], normal[cand])
    apart |= (side >= -slack).all(axis=0) | (side <= slack).all(axis=0)  # the blocker's plane
    rest = np.nonzero(~apart)[0]
    if len(rest):
        hullEdges = np.array([corners[i][(a + 1) % 3] - corners[i][a] for a in range(3)] +
                             [corners[j][(a + 1) % 3] - corners[j][a] for a in range(3)] +
                             [corners[j][b] - corners[i][a] for a in range(3) for b in range(3)])
        tr = t[rest]
        edges = np.stack([tr[:, (a + 1) % 3] - tr[:, a] for a in range(3)], axis=1)
        axes = np.cross(edges[:, :, None, :], hullEdges[None, None, :, :]).reshape(len(rest), 45, 3)
        pt = np.einsum("rad,rvd->rav", axes, tr)
        ph = np.einsum("rad,hd->rah", axes, hull)
        length = np.linalg.norm(axes, axis=2)
        tol = slack * length
        gap = (pt.max(axis=2) <= ph.min(axis=2) + tol) | (ph.max(axis=2) <= pt.min(axis=2) + tol)
        apart[rest] = (gap & (length > 1e-12)).any(axis=1)
    return apart.all()


def nearField(reach, files):
    with h5py.File(files[0], "r") as f:
        vertices, triangles = f["mesh/vertices"][:], f["mesh/triangles"][:]
    corners = vertices[triangles]
    n = len(triangles)
    normal = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    centroid = corners.mean(axis=1)
    radius = np.linalg.norm(corners - centroid[:, None, :], axis=2).max(axis=1)
    slack = 1e-9 * np.linalg.norm(vertices.max(axis=0) - vertices.min(axis=0))
    proven = set()
    tried = 0
    for i in range(n):
        distance = np.linalg.norm(centroid - centroid[i], axis=1)
        for j in np.nonzero((distance <= reach) & (np.arange(n) != i))[0]:
            hj = (corners[j] - corners[i][0]) @ normal[i]
            hi = (corners[i] - corners[j][0]) @ normal[j]
            if (hj < -slack).any() or not (hj > slack).any() or (hi < -slack).any() or \
                    not (hi > slack).any():
                continue
            tried += 1
            if provenUnoccluded(corners, normal, centroid, radius, slack, i, j, distance[j]):
                proven.add((i, j))
    runs = [load(p) for p in files]
    whole, rest = [], []
    for r in runs:
        exact = np.array([(a, b) in proven for a, b in zip(r["row"], r["col"])], bool)
        whole.append(np.bincount(r["row"], weights=r["val"], minlength=n))
        rest.append(np.bincount(r["row"], weights=np.where(exact, 0, r["val"]), minlength=n))
    whole, rest = np.array(whole), np.array(rest)
    sd, sdRest = whole.std(axis=0, ddof=1), rest.std(axis=0, ddof=1)
    ground = runs[0]["face"] == 0
    print(f"near field within {reach:g}: {tried} facing pairs, {len(proven)} proven unoccluded "
          f"({len(proven) / n:.1f} a row, {np.mean(whole.mean(0) - rest.mean(0)):.3f} of the mean "
          f"row sum {np.mean(whole.mean(0)):.3f}); row-sum spread {rms(sd):.3e} sampled -> "
          f"{rms(sdRest):.3e} with those pairs exact (ground {rms(sd[ground]):.3e} -> "
          f"{rms(sdRest[ground]):.3e})")


if __name__ == "__main__":
    if len(sys.argv) > 2 and sys.argv[1] == "spread":
        spread(sys.argv[2:])
    elif len(sys.argv) > 3 and sys.argv[1] == "near-field":
        nearField(float(sys.argv[2]), sys.argv[3:])
    else:
        sys.exit(__doc__)
