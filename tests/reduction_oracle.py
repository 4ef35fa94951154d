"""The model rebuilt from a symmetry-based reduction (generate_symmetry_based_reduction), and
its distance to the input, computed here with numpy and a kd-tree, sharing nothing with the
plugin's own reconstruction: the tests and the benchmark judge the filter by it."""
import numpy as np
from scipy.spatial import cKDTree

import scenes


def instances_of(out):
    """[(4x4 matrix, faces of the reduced mesh)] from the filter's returned values."""
    matrices = np.asarray(out["instance_transforms"]).reshape(-1, 4, 4)
    counts = np.asarray(out["instance_face_counts"], dtype=int)
    faces = np.split(np.asarray(out["instance_faces"], dtype=int), np.cumsum(counts)[:-1])
    return list(zip(matrices, faces))


def rebuilt(Vr, Fr, instances):
    """The reduced mesh (Vr, Fr) with every instance's faces transformed, as one (V, F)."""
    Vs, Fs, offset = [Vr], [Fr], len(Vr)
    for M, faces in instances:
        W = Vr @ M[:3, :3].T + M[:3, 3]
        Vs.append(W)
        Fs.append(Fr[faces] + offset)
        offset += len(W)
    return np.vstack(Vs), np.vstack(Fs)


def farthest(A, FA, B, FB, rng, n=120000):
    """Largest distance from samples of surface A (and the vertices of its faces) to dense
    samples of surface B (an upper bound on the surface distance, plus about the spacing of
    B's samples).  Vertices no face uses are no part of a surface (rebuilt() moves every vertex
    of the reduced mesh with each instance, used or not)."""
    PA = np.vstack([scenes.sample_surface(A, FA, n // 4, rng), A[np.unique(FA)]])
    PB = np.vstack([scenes.sample_surface(B, FB, n, rng), B[np.unique(FB)]])
    return float(cKDTree(PB).query(PA)[0].max())


def two_sided(V, F, W, G, rng):
    """The larger of the two one-sided distances between surfaces (V, F) and (W, G)."""
    return max(farthest(V, F, W, G, rng), farthest(W, G, V, F, rng))
