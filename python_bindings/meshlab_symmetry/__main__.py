"""Command line: detect partial symmetries in a mesh file.

    meshlab-symmetry detect INPUT -o OUTDIR [--sample-count N ...every parameter of detect]

writes into OUTDIR <stem>.symmetry.ply (the input with per-vertex quality = signed
deviation from symmetry and its colour ramp), <stem>.symmetry_<k>_source.ply and
<stem>.symmetry_<k>_target.ply (the patches of symmetry k) and symmetries.json
(SymmetryResult.to_json), and prints a table of the symmetries.  With --report also
report.html and its pictures (meshlab_symmetry.pictures).  It runs the compiled core with a
progress bar on stderr (on a terminal, or with --progress); --engine filter runs the MeshLab
filter through pymeshlab instead.

The older form stays as it was:

    python -m meshlab_symmetry INPUT [--output-prefix P]
        [--group rigid|similarity|reflections|translations] [--seed N]

Writes <P>.symmetry.ply and <P>.symmetry.json (the symmetry graph), where P is the input
path without its extension unless --output-prefix is given (a directory there means
<directory>/<input stem>), and prints what was found.

    meshlab-symmetry script MESH -o detect.mlx [--verification-tolerance 0.02 ...]

writes a filter script for Debian 12's meshlabserver (MeshLab 2020.09) that runs the filter
with these parameters, its lengths made absolute for the diagonal of MESH
(meshlab_symmetry.filter_script).

    meshlab-symmetry batch INPUT... -o OUTDIR [--jobs N | --scheduler ADDRESS] [parameters]

runs the core over many meshes in parallel worker processes (or a Dask cluster), resumable,
one JSON per mesh plus summary.csv (meshlab_symmetry.batch).

Every form reports an error as one line on stderr and exits non-zero.
"""
import argparse
import contextlib
import os
import sys

import numpy as np
import pymeshlab

from . import FILTER_NAME
from .api import (GROUPS, PARAMETERS, _detect_in_meshset, _detect_with_core, load_mesh_file,  # noqa: F401
                  obj_face_index_problem)
from .symmetry_graph import _mesh_ids, symmetry_graph, to_json

#: the console script's name, which begins its error lines
PROG = "meshlab-symmetry"


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


def _table(result, graph, kinds=None):
    """The table of symmetries; ``kinds`` (one per symmetry, the words of
    SymmetryResult) replaces the coarser words of _kind."""
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
            kind = kinds[e["symmetry"]] if kinds else _kind(e)
            lines.append(f"{e['symmetry']:>3}  {kind:<20} {patches:<24} {e['scale']:>7.4f} "
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


def _error_message(error):
    """The exception's sentence on one line, without pymeshlab's "Failed to apply filter" preamble."""
    message = " ".join(line.strip() for line in str(error).splitlines() if line.strip())
    return message.split("Details:", 1)[-1].strip()


def main(argv=None):
    """`meshlab-symmetry detect ...` when the first argument is `detect`, else the older form."""
    argv = sys.argv[1:] if argv is None else list(argv)
    if argv and argv[0] == "detect":
        return _detect_command(argv[1:])
    if argv and argv[0] == "script":
        return _script_command(argv[1:])
    if argv and argv[0] == "batch":
        return _batch_command(argv[1:])
    return _prefix_command(argv)


def _prefix_command(argv):
    parser = argparse.ArgumentParser(prog="python -m meshlab_symmetry",
                                     description="Detect partial and approximate symmetries in a triangle mesh. "
                                                 "`meshlab-symmetry detect --help` shows the form with every "
                                                 "parameter.")
    parser.add_argument("input", help="mesh file (any format pymeshlab reads)")
    parser.add_argument("--output-prefix", help="write <P>.symmetry.ply and <P>.symmetry.json "
                                                "(default: next to the input)")
    parser.add_argument("--group", choices=sorted(GROUPS, key=GROUPS.get), default="rigid",
                        help="transformation group searched (default: rigid)")
    parser.add_argument("--seed", type=int, default=0, help="random seed (default: 0)")
    args = parser.parse_args(argv)

    try:
        prefix = _output_prefix(args.input, args.output_prefix)
        ms = pymeshlab.MeshSet()
        load_mesh_file(ms, args.input)
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
        print(f"meshlab_symmetry: error: {_error_message(e)}", file=sys.stderr)
        return 1
    print(_table(result, graph))
    print(f"wrote {prefix}.symmetry.ply and {prefix}.symmetry.json")
    return 0


class _OneLineParser(argparse.ArgumentParser):
    """Reports a usage error as the one line every other error is (argparse prints the
    usage first)."""

    def error(self, message):
        print(f"{PROG}: error: {message}", file=sys.stderr)
        sys.exit(2)


def _add_parameter_options(parser):
    """One option per parameter of detect, in detect's units."""
    for p in PARAMETERS:
        flag = "--" + p.name.replace("_", "-")
        text = f"{p.meaning} ({p.unit}; default: %(default)s)"
        if p.convert == "group":
            parser.add_argument(flag, choices=list(GROUPS), default="rigid",
                                help=f"{p.meaning} (a name; default: %(default)s)")
        elif isinstance(p.default, bool):
            parser.add_argument(flag, action=argparse.BooleanOptionalAction, default=p.default, help=text)
        else:
            metavar = "N" if isinstance(p.default, int) else "FRACTION" if p.unit.startswith("fraction") else "X"
            parser.add_argument(flag, type=type(p.default), default=p.default, metavar=metavar, help=text)


def _script_command(argv):
    """`meshlab-symmetry script MESH -o detect.mlx [parameters]`: a filter script for
    meshlabserver 2020.09, whose lengths are absolute, made for MESH's diagonal."""
    from .filter_script import meshlabserver_script
    parser = _OneLineParser(
        prog=f"{PROG} script",
        description="Write a MeshLab 2020.09 filter script (.mlx) that runs the symmetry filter in meshlabserver "
                    "(`xvfb-run -a meshlabserver -i MESH -o out.ply -m vq vc -s SCRIPT`). meshlabserver needs every "
                    "parameter in the script and reads lengths in the mesh's units, so the script is made for the "
                    "bounding-box diagonal of MESH; it serves every mesh of about that size.")
    parser.add_argument("input", help="mesh file whose diagonal sets the lengths (any format pymeshlab reads)")
    parser.add_argument("-o", "--output", required=True, metavar="SCRIPT", help="the .mlx file to write")
    parser.add_argument("--create-patch-layers", action=argparse.BooleanOptionalAction, default=False,
                        help="add the patch layers (meshlabserver saves only the input; default: %(default)s)")
    _add_parameter_options(parser)
    args = parser.parse_args(argv)
    parameters = {p.name: getattr(args, p.name) for p in PARAMETERS}
    try:
        ms = pymeshlab.MeshSet()
        load_mesh_file(ms, args.input)
        diagonal = ms.current_mesh().bounding_box().diagonal()
        text = meshlabserver_script(diagonal, create_patch_layers=args.create_patch_layers, **parameters)
        with open(args.output, "w") as f:
            f.write(text)
    except (pymeshlab.PyMeshLabException, OSError, ValueError) as e:
        print(f"{PROG}: error: {_error_message(e)}", file=sys.stderr)
        return 1
    print(f"wrote {args.output} (lengths for a bounding-box diagonal of {diagonal:.6g})")
    return 0


def _batch_command(argv):
    """`meshlab-symmetry batch INPUT... -o OUTDIR`: every mesh, in parallel, resumable
    (meshlab_symmetry.batch)."""
    from . import batch
    parser = _OneLineParser(
        prog=f"{PROG} batch",
        description="Detect symmetries in many meshes: files, folders (searched recursively for "
                    f"{', '.join(batch.MESH_EXTENSIONS)}) and glob patterns. Writes OUTDIR/<path relative to its input>.json "
                    "(the result, as `detect` writes symmetries.json) per mesh and OUTDIR/summary.csv. Meshes whose JSON "
                    "is already in OUTDIR are skipped, so a stopped batch resumes; a mesh that fails is reported in the "
                    "summary and the others go on.")
    parser.add_argument("inputs", nargs="+", metavar="INPUT", help="mesh file, folder or glob pattern")
    parser.add_argument("-o", "--output-dir", required=True, metavar="OUTDIR", help="where the results go")
    parser.add_argument("-j", "--jobs", type=int, default=None, metavar="N",
                        help="local worker processes, each running the core on one thread (default: one per core)")
    parser.add_argument("--scheduler", metavar="ADDRESS",
                        help="run on the workers of this Dask distributed scheduler (tcp://host:8786) instead of "
                             "local processes; the workers need this package and must read the input paths")
    parser.add_argument("--progress", action=argparse.BooleanOptionalAction, default=True,
                        help="a progress line on stderr, redrawn on a terminal (default: %(default)s)")
    _add_parameter_options(parser)
    args = parser.parse_args(argv)
    if args.jobs is not None and args.jobs < 1:
        parser.error(f"--jobs is {args.jobs}, but it must be at least 1")
    parameters = {p.name: getattr(args, p.name) for p in PARAMETERS}
    parameters["transformation_group"] = GROUPS[args.transformation_group]
    try:
        outcomes = batch.run_batch(args.inputs, args.output_dir, parameters, jobs=args.jobs,
                                   scheduler=args.scheduler,
                                   on_outcome=batch.ProgressLine(sys.stderr) if args.progress else None)
    except (OSError, ValueError, RuntimeError) as e:
        print(f"{PROG}: error: {_error_message(e)}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print(f"\n{PROG}: interrupted; the results written so far stay, and a rerun resumes from them",
              file=sys.stderr)
        return 130
    counts = {status: sum(o.status == status for o in outcomes) for status in ("done", "skipped", "failed")}
    print(f"{counts['done']} analysed, {counts['skipped']} already done, {counts['failed']} failed; "
          f"results and {batch.SUMMARY} in {args.output_dir}")
    return 1 if counts["failed"] else 0


def _detect_parser():
    parser = _OneLineParser(
        prog=f"{PROG} detect",
        description="Detect partial and approximate symmetries in a triangle mesh (Mitra, Guibas, Pauly 2006). "
                    "Writes into OUTDIR <stem>.symmetry.ply (the mesh with per-vertex quality = signed deviation "
                    "from symmetry, as a fraction of the diagonal, and its colour ramp), "
                    "<stem>.symmetry_<k>_source.ply and <stem>.symmetry_<k>_target.ply (the patches of "
                    "symmetry k) and symmetries.json, and prints a table of the symmetries.")
    parser.add_argument("input", help="mesh file (any format pymeshlab reads)")
    parser.add_argument("-o", "--output-dir", required=True, metavar="OUTDIR",
                        help="directory the files are written to (made if missing)")
    parser.add_argument("--report", action="store_true",
                        help="also write report.html with pictures of the deviation, the patches and the detector's "
                             "transformation space (PNG files beside it) and a table of the symmetries")
    parser.add_argument("--engine", choices=("core", "filter"), default="core",
                        help="'core' runs the compiled core, with a progress bar; 'filter' runs the MeshLab filter "
                             "through pymeshlab, as a filter script would, and saves the mesh as MeshLab holds it "
                             "(every attribute it read); the same symmetries for the same seed (default: %(default)s)")
    parser.add_argument("--progress", action=argparse.BooleanOptionalAction, default=None,
                        help="draw the core's progress bar on stderr (default: when stderr is a terminal)")
    _add_parameter_options(parser)
    return parser


def _detect_command(argv):
    parser = _detect_parser()
    args = parser.parse_args(argv)
    parameters = {p.name: getattr(args, p.name) for p in PARAMETERS}
    parameters["transformation_group"] = GROUPS[args.transformation_group]
    show_progress = sys.stderr.isatty() if args.progress is None else args.progress
    if show_progress and args.engine != "core":
        parser.error("--progress needs --engine core (pymeshlab runs a filter without a callback)")
    try:
        ms = pymeshlab.MeshSet()
        load_mesh_file(ms, args.input)
        mesh_id = ms.current_mesh_id()
        if args.engine == "core":
            with _ProgressBar(sys.stderr) if show_progress else contextlib.nullcontext() as bar:
                result = _detect_with_core(ms, parameters, bar)
            mesh_id = _add_outputs_to_meshset(ms, mesh_id, result)
        else:
            result = _detect_in_meshset(ms, parameters)
        written = _write_outputs(ms, mesh_id, result, args.input, args.output_dir)
        if args.report:
            written += _write_report(args.input, result, args.output_dir)
    except (pymeshlab.PyMeshLabException, OSError, ValueError, RuntimeError) as e:
        print(f"{PROG}: error: {_error_message(e)}", file=sys.stderr)
        return 1
    except MemoryError:
        print(f"{PROG}: error: the analysis ran out of memory; lower --sample-count, --pair-sample-count or "
              "--max-working-vertices", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print(f"\n{PROG}: interrupted; no file written after the detection stopped", file=sys.stderr)
        return 130
    print(_table({**result.timings, **result.work}, result.graph, [s.kind for s in result.symmetries]))
    print(f"wrote {len(written)} files to {args.output_dir}")
    return 0


class _ProgressBar:
    """`[#########...........]  45% Mean-shift clustering in transformation space`, redrawn in
    place on a terminal (or appended, one line per stage, elsewhere); called as the core's
    progress callback."""
    WIDTH = 30

    def __init__(self, stream):
        self.stream, self.stage = stream, None
        self.terminal = stream.isatty()

    def __call__(self, percent, stage):
        if not self.terminal and stage == self.stage and percent < 100:
            return  # a log file gets a line per stage, not one per step
        self.stage = stage
        filled = self.WIDTH * percent // 100
        line = f"[{'#' * filled}{'.' * (self.WIDTH - filled)}] {percent:3d}% {stage}"
        self.stream.write(f"\r{line:<100}" if self.terminal else line + "\n")
        self.stream.flush()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        if self.terminal:
            self.stream.write("\n")
            self.stream.flush()
        return False


def _add_outputs_to_meshset(ms, mesh_id, result):
    """What the filter leaves in the MeshSet, from the core's result: on the input mesh the
    per-vertex quality (the signed deviation) and MeshLab's red-green-blue colour ramp over
    -max..max of it, grey where no symmetry holds; a layer symmetry_<k>_source/_target per
    patch (its vertices and the faces among them), for _write_outputs."""
    mesh = ms.mesh(mesh_id)
    vertices, faces = mesh.vertex_matrix(), mesh.face_matrix()
    extent = float(np.abs(result.deviation).max()) if len(result.deviation) else 0.0
    extent = extent if extent > 0 else 1e-6  # all exact: the ramp's centre colour everywhere
    ramp = pymeshlab.MeshSet()
    ramp.add_mesh(pymeshlab.Mesh(vertex_matrix=vertices, face_matrix=faces, v_scalar_array=result.deviation))
    ramp.compute_color_from_scalar_per_vertex(minval=-extent, maxval=extent)
    colours = ramp.current_mesh().vertex_color_matrix()
    colours[result.symmetry_id < 0] = [128 / 255, 128 / 255, 128 / 255, 1.0]
    ms.add_mesh(pymeshlab.Mesh(vertex_matrix=vertices, face_matrix=faces, v_scalar_array=result.deviation,
                               v_color_matrix=colours), mesh.label())
    coloured = ms.current_mesh_id()
    ms.set_current_mesh(mesh_id)
    ms.delete_current_mesh()
    for s in result.symmetries:
        for side, rows in (("source", s.source_vertices), ("target", s.target_vertices)):
            inside = np.full(len(vertices), -1, dtype=np.int64)
            inside[rows] = np.arange(len(rows))
            kept = faces[(inside[faces] >= 0).all(axis=1)]
            ms.add_mesh(pymeshlab.Mesh(vertex_matrix=vertices[rows], face_matrix=inside[kept].astype(np.int32)),
                        f"symmetry_{s.index}_{side}")
    ms.set_current_mesh(coloured)
    return coloured


def _write_report(input_path, result, output_dir):
    """report.html and its pictures; matplotlib is imported only when a report is asked for."""
    from .pictures import REPORT_PICTURES, report_html
    report = report_html(input_path, result, output_dir)
    return [os.path.join(output_dir, name) for name, _, _ in REPORT_PICTURES] + [report]


def _write_outputs(ms, mesh_id, result, input_path, output_dir):
    """Writes the files of `meshlab-symmetry detect` and returns their paths."""
    stem = os.path.splitext(os.path.basename(input_path))[0]
    os.makedirs(output_dir, exist_ok=True)
    written = []
    for layer in _mesh_ids(ms):
        ms.set_current_mesh(layer)
        if layer == mesh_id:
            path = os.path.join(output_dir, f"{stem}.symmetry.ply")
            ms.save_current_mesh(path, save_vertex_quality=True, save_vertex_color=True)
        else:  # symmetry_<k>_source or symmetry_<k>_target
            path = os.path.join(output_dir, f"{stem}.{ms.current_mesh().label()}.ply")
            ms.save_current_mesh(path)
        written.append(path)
    path = os.path.join(output_dir, "symmetries.json")
    with open(path, "w") as f:
        f.write(result.to_json() + "\n")
    return written + [path]


if __name__ == "__main__":
    sys.exit(main())
