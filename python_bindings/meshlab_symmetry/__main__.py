"""Command line: detect partial symmetries in a mesh file.

    python -m meshlab_symmetry INPUT [--output-prefix P]
        [--group rigid|similarity|reflections|translations] [--seed N]

Writes <P>.symmetry.ply (the input with per-vertex quality = signed deviation from
symmetry and its colour ramp) and <P>.symmetry.json (the symmetry graph), where P is
the input path without its extension unless --output-prefix is given (a directory
there means <directory>/<input stem>), and prints what was found.
"""
import argparse
import os
import sys

import pymeshlab

from . import FILTER_NAME
from .symmetry_graph import symmetry_graph, to_json

# Index of the filter's transformation_group enum (public API).
GROUPS = {"rigid": 0, "similarity": 1, "reflections": 2, "translations": 3}


def _kind(edge):
    if edge.get("continuous_kind", "discrete") != "discrete":
        return f"{edge['continuous_kind']} family"
    if edge["is_reflection"]:
        return "reflection"
    if abs(edge["scale"] - 1) > 1e-6:
        return "similarity"
    linear = [row[:3] for row in edge["transform"][:3]]
    if all(abs(linear[i][j] - (i == j)) < 1e-6 for i in range(3) for j in range(3)):
        return "translation"
    return "rotation"


def _word(letters):
    return " ".join(f"{'+' if w > 0 else '-'}g{abs(w) - 1}" for w in letters) or "-"


def _table(result, graph):
    nodes = graph["nodes"]
    lines = [f"{graph['symmetry_count']} symmetries, {len(graph['generators'])} generators, "
             f"{len(nodes)} patches"]
    if graph["edges"]:
        lines.append(f"{'#':>3}  {'kind':<20} {'source -> target':<24} {'scale':>7} {'rms %diag':>9} "
                     f"{'area %':>7} {'support':>7}  basis")
        for e in graph["edges"]:
            s, t = nodes[e["source"]], nodes[e["target"]]
            patches = f"{s['name']}({s['vertex_count']}) -> {t['name']}({t['vertex_count']})"
            if len(patches) > 24:
                patches = f"p{s['id']}({s['vertex_count']}) -> p{t['id']}({t['vertex_count']})"
            basis = "generator" if e["is_generator"] else _word(e["word"])
            lines.append(f"{e['symmetry']:>3}  {_kind(e):<20} {patches:<24} {e['scale']:>7.4f} "
                         f"{100 * e['rms_error']:>9.3f} {100 * s['area_fraction']:>7.2f} {e['support']:>7}  {basis}")
    times = [(name, float(result.get(f"seconds_{name}", 0.0)))
             for name in ("signatures", "pairing", "clustering", "verification")]
    lines.append("time: " + ", ".join(f"{name} {t:.2f} s" for name, t in times)
                 + f" (total {sum(t for _, t in times):.2f} s)")
    lines.append(f"work: {int(result.get('samples', 0))} samples, {int(result.get('pruned_samples', 0))} after "
                 f"pruning, {int(result.get('pairs', 0))} pairs, {int(result.get('clusters', 0))} clusters")
    return "\n".join(lines)


def _output_prefix(input_path, prefix):
    stem = os.path.splitext(os.path.basename(input_path))[0]
    if prefix is None:
        return os.path.join(os.path.dirname(os.path.abspath(input_path)), stem)
    if os.path.isdir(prefix) or prefix.endswith(os.sep):
        return os.path.join(prefix, stem)
    return prefix


def obj_face_index_problem(path):
    """For an OBJ file whose faces use vertex indices outside its vertex list, a sentence
    saying so; None otherwise (and for other formats).  MeshLab's OBJ reader leaves such
    faces pointing past its vertex array, and the process then crashes when it frees the
    mesh (assimp's invalid/malformed.obj, about one run in two), so the file is refused
    before pymeshlab reads it."""
    if not path.lower().endswith(".obj"):
        return None
    vertices, faces = 0, []
    with open(path, errors="replace") as f:
        for line in f:
            token = line.split(maxsplit=1)
            if not token:
                continue
            if token[0] == "v":
                vertices += 1
            elif token[0] == "f" and len(token) > 1:
                faces.append((vertices, token[1].split()))
    for seen, corners in faces:
        for corner in corners:
            try:
                index = int(corner.split("/")[0])
            except ValueError:
                return f"cannot read {path}: a face has the vertex reference '{corner}', which is not a number"
            absolute = seen + index + 1 if index < 0 else index
            if not 1 <= absolute <= vertices:
                return (f"cannot read {path}: a face refers to vertex {index}, but the file has {vertices} "
                        "vertices (the file is malformed; repair it in the program that wrote it)")
    return None


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python -m meshlab_symmetry",
                                     description="Detect partial and approximate symmetries in a triangle mesh.")
    parser.add_argument("input", help="mesh file (any format pymeshlab reads)")
    parser.add_argument("--output-prefix", help="write <P>.symmetry.ply and <P>.symmetry.json "
                                                "(default: next to the input)")
    parser.add_argument("--group", choices=sorted(GROUPS, key=GROUPS.get), default="rigid",
                        help="transformation group searched (default: rigid)")
    parser.add_argument("--seed", type=int, default=0, help="random seed (default: 0)")
    args = parser.parse_args(argv)

    try:
        if not os.path.isfile(args.input):
            raise OSError(f"no such file: {args.input}")
        prefix = _output_prefix(args.input, args.output_prefix)
        problem = obj_face_index_problem(args.input)
        if problem:
            raise ValueError(problem)
        ms = pymeshlab.MeshSet()
        try:
            ms.load_new_mesh(os.path.abspath(args.input))
        except MemoryError:
            # pymeshlab's readers reserve what the header says (assimp's OutOfMemory.off
            # announces 353 billion vertices) and let std::bad_alloc through.
            raise OSError(f"cannot read {args.input}: the file asks for more memory than there is "
                          "(its header's vertex or face count is probably wrong)") from None
        mesh_id = ms.current_mesh_id()
        result = getattr(ms, FILTER_NAME)(transformation_group=GROUPS[args.group], random_seed=args.seed,
                                          create_patch_layers=True)
        graph = symmetry_graph(ms, result, mesh_id)
        if os.path.dirname(prefix):
            os.makedirs(os.path.dirname(prefix), exist_ok=True)
        ms.set_current_mesh(mesh_id)
        ms.save_current_mesh(prefix + ".symmetry.ply", save_vertex_quality=True, save_vertex_color=True)
        with open(prefix + ".symmetry.json", "w") as f:
            f.write(to_json(graph) + "\n")
    except (pymeshlab.PyMeshLabException, OSError, ValueError) as e:
        message = " ".join(line.strip() for line in str(e).splitlines() if line.strip())
        message = message.split("Details:", 1)[-1].strip()  # drop pymeshlab's "Failed to apply filter"
        print(f"meshlab_symmetry: error: {message}", file=sys.stderr)
        return 1
    print(_table(result, graph))
    print(f"wrote {prefix}.symmetry.ply and {prefix}.symmetry.json")
    return 0


if __name__ == "__main__":
    sys.exit(main())
