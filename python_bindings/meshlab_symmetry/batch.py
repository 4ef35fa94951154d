"""Symmetry detection over many mesh files: `meshlab-symmetry batch`.

    meshlab-symmetry batch INPUT... -o OUTDIR [--jobs N | --scheduler ADDRESS] [parameters]

Each INPUT is a mesh file, a folder (searched recursively for the formats below) or a glob
pattern.  For every mesh the compiled core (the filter's pipeline, ``detect(engine="core")``)
runs in a worker process, and OUTDIR receives ``<path relative to its input>.json``
(SymmetryResult.to_json) and ``summary.csv`` (one row per mesh).  A mesh whose JSON is
already there is skipped, so a stopped batch resumes where it was; a mesh that fails is a
row with its error, and the others go on.

Workers are local processes (``--jobs``, default one per core, each running the core on one
thread) or, for datasets that outgrow one machine, the workers of a Dask distributed cluster
(``--scheduler tcp://host:8786``): every worker must have this package installed and read
the input paths; the results come back to this process, which alone writes OUTDIR.
"""
import concurrent.futures
import csv
import dataclasses
import glob
import multiprocessing
import os
import sys
import time
from typing import Any, Callable, Iterable, Iterator, Optional, Sequence

from .geometry import FAMILY_KINDS

#: the file formats a folder is searched for (those pymeshlab reads that hold triangles)
MESH_EXTENSIONS = (".ply", ".obj", ".off", ".stl")
SUMMARY = "summary.csv"
SUMMARY_COLUMNS = ("mesh", "status", "symmetries", "generators", "continuous", "vertices", "seconds", "error")


@dataclasses.dataclass(frozen=True)
class Job:
    """One mesh of a batch: its path as given, the JSON it gets (relative to OUTDIR), and
    its absolute path, which is what a worker opens (pymeshlab changes a process's working
    folder when it loads a mesh, so a worker's next relative path would miss)."""
    mesh: str
    result: str
    absolute: str


@dataclasses.dataclass
class Outcome:
    """What became of one job: status "done", "skipped" (its JSON was there) or "failed"."""
    job: Job
    status: str
    symmetries: Optional[int] = None
    generators: Optional[int] = None
    continuous: Optional[int] = None
    vertices: Optional[int] = None
    seconds: Optional[float] = None
    error: str = ""

    def row(self) -> dict[str, Any]:
        return {"mesh": self.job.mesh, "status": self.status, "symmetries": _blank(self.symmetries),
                "generators": _blank(self.generators), "continuous": _blank(self.continuous),
                "vertices": _blank(self.vertices),
                "seconds": "" if self.seconds is None else f"{self.seconds:.2f}", "error": self.error}


def _blank(value):
    return "" if value is None else value


def find_jobs(inputs: Sequence[str]) -> list[Job]:
    """The meshes named by files, folders (recursive) and glob patterns, each once, in a
    stable order, with the JSON path each gets: its path relative to the folder or pattern
    root it was found under, with .json appended (model.ply -> model.ply.json), so meshes
    of the same name in different folders or formats do not collide.  Raises
    FileNotFoundError for an input that names nothing."""
    jobs: dict[str, Job] = {}
    for given in inputs:
        found = list(_meshes_of(given))
        if not found:
            raise FileNotFoundError(f"{given} names no mesh file ({', '.join(MESH_EXTENSIONS)})")
        for path, root in found:
            real = os.path.realpath(path)
            if real not in jobs:
                jobs[real] = Job(mesh=path, result=os.path.relpath(path, root) + ".json",
                                 absolute=os.path.abspath(path))
    ordered = sorted(jobs.values(), key=lambda j: j.result)
    clashes = _duplicates(j.result for j in ordered)
    if clashes:
        raise ValueError(f"two inputs would write the same result {clashes[0]}; give their folders separately "
                         "or run them in two batches")
    return ordered


def _meshes_of(given: str) -> Iterator[tuple[str, str]]:
    """(mesh path, the root its result path is relative to) for one input."""
    if os.path.isdir(given):
        for folder, _, files in os.walk(given):
            for name in sorted(files):
                if name.lower().endswith(MESH_EXTENSIONS):
                    yield os.path.join(folder, name), given
    elif os.path.isfile(given):
        yield given, os.path.dirname(given) or "."
    else:
        root = _glob_root(given)
        for path in sorted(glob.glob(given, recursive=True)):
            if os.path.isfile(path) and path.lower().endswith(MESH_EXTENSIONS):
                yield path, root


def _glob_root(pattern: str) -> str:
    """The folder part of a glob pattern before its first wildcard."""
    parts = pattern.split(os.sep)
    fixed = []
    for part in parts[:-1]:
        if glob.has_magic(part):
            break
        fixed.append(part)
    return os.sep.join(fixed) or ("." if not pattern.startswith(os.sep) else os.sep)


def _duplicates(values: Iterable[str]) -> list[str]:
    seen, twice = set(), []
    for v in values:
        if v in seen:
            twice.append(v)
        seen.add(v)
    return twice


def analyse(mesh: str, parameters: dict[str, Any]) -> dict[str, Any]:
    """Detection on one mesh file in this process (a worker): the result's JSON and the
    figures of its summary row, or the error.  Never raises for a bad mesh."""
    from .api import detect
    start = time.perf_counter()
    try:
        result = detect(mesh, engine="core", **parameters)
    except Exception as e:  # a worker reports every failure of its mesh, whatever it is (MemoryError too)
        return {"error": _one_line(e)}
    return {"json": result.to_json(), "seconds": time.perf_counter() - start, **_figures(result)}


def _one_line(error: BaseException) -> str:
    """An exception as one line of the summary: its type and its message, whitespace folded."""
    return " ".join(f"{type(error).__name__}: {error}".split())


def _figures(result) -> dict[str, int]:
    continuous = sum(1 for s in result.symmetries if s.kind in FAMILY_KINDS.values())
    return {"symmetries": len(result.symmetries), "generators": int(result.work.get("generator_count", 0)),
            "continuous": continuous, "vertices": int(result.vertex_count)}


def _skipped(job: Job, output_dir: str) -> Optional[Outcome]:
    """The outcome of a job whose JSON is already in OUTDIR and readable, else None."""
    from .result import SymmetryResult
    path = os.path.join(output_dir, job.result)
    if not os.path.exists(path):
        return None
    try:
        with open(path) as f:
            result = SymmetryResult.from_json(f.read())
    except (OSError, ValueError, KeyError, TypeError):
        return None  # a partial or foreign file: analysed again and replaced
    return Outcome(job, "skipped", **_figures(result))


def _write_atomically(path: str, text: str) -> None:
    os.makedirs(os.path.dirname(path) or ".", exist_ok=True)
    with open(path + ".tmp", "w") as f:
        f.write(text)
    os.replace(path + ".tmp", path)


def _single_threaded_worker() -> None:
    """Each local worker runs the core on one thread: the workers already use every core."""
    os.environ["OMP_NUM_THREADS"] = "1"


def _local_results(jobs: list[Job], parameters: dict[str, Any], workers: int) -> Iterator[tuple[Job, dict]]:
    context = multiprocessing.get_context("spawn")  # fresh interpreters: no state forked from this one
    with concurrent.futures.ProcessPoolExecutor(max_workers=workers, mp_context=context,
                                                initializer=_single_threaded_worker) as pool:
        futures = {pool.submit(analyse, job.absolute, parameters): job for job in jobs}
        try:
            for future in concurrent.futures.as_completed(futures):
                job = futures[future]
                try:
                    yield job, future.result()
                except concurrent.futures.process.BrokenProcessPool:
                    raise
                except Exception as e:  # the worker died on this mesh
                    yield job, {"error": _one_line(e)}
        except KeyboardInterrupt:
            for future in futures:
                future.cancel()
            raise


def _dask_results(jobs: list[Job], parameters: dict[str, Any], scheduler: str) -> Iterator[tuple[Job, dict]]:
    try:
        from distributed import Client, as_completed
    except ImportError as e:
        raise RuntimeError("--scheduler needs Dask distributed (pip install distributed)") from e
    with Client(scheduler) as client:
        futures = client.map(analyse, [job.absolute for job in jobs], parameters=parameters,
                             key=[f"meshlab-symmetry-{i}-{os.path.basename(job.mesh)}" for i, job in enumerate(jobs)],
                             pure=False)
        job_of = {future.key: job for future, job in zip(futures, jobs)}
        for future in as_completed(futures):
            job = job_of[future.key]
            try:
                yield job, future.result()
            except Exception as e:  # the worker was lost, or its process died on this mesh
                yield job, {"error": _one_line(e)}


def run_batch(inputs: Sequence[str], output_dir: str, parameters: dict[str, Any], *, jobs: Optional[int] = None,
              scheduler: Optional[str] = None,
              on_outcome: Optional[Callable[[Outcome, int, int], None]] = None) -> list[Outcome]:
    """Detects symmetries in every mesh of ``inputs`` (see find_jobs), writing each result
    JSON and summary.csv into ``output_dir``, and returns the outcomes in the order of the
    jobs.  Meshes whose JSON is already there are skipped.  ``jobs`` local worker
    processes (default: one per core) or the workers of the Dask scheduler at
    ``scheduler`` do the work.  ``on_outcome(outcome, finished, total)`` is called in this
    process after each mesh.  summary.csv is written after every mesh, so a stopped batch
    leaves a summary of what it did."""
    all_jobs = find_jobs(inputs)
    os.makedirs(output_dir, exist_ok=True)
    outcomes: dict[Job, Outcome] = {}
    todo = []
    for job in all_jobs:
        skipped = _skipped(job, output_dir)
        if skipped:
            outcomes[job] = skipped
        else:
            todo.append(job)
    finished = 0
    for outcome in outcomes.values():  # the skipped ones, counted up one by one
        finished += 1
        if on_outcome:
            on_outcome(outcome, finished, len(all_jobs))
    _write_summary(output_dir, all_jobs, outcomes)
    if todo:
        workers = max(1, min(jobs or os.cpu_count() or 1, len(todo)))
        results = (_dask_results(todo, parameters, scheduler) if scheduler
                   else _local_results(todo, parameters, workers))
        for job, answer in results:
            outcomes[job] = _record(job, answer, output_dir)
            finished += 1
            if on_outcome:
                on_outcome(outcomes[job], finished, len(all_jobs))
            _write_summary(output_dir, all_jobs, outcomes)  # after every mesh: a stopped batch keeps it
    return [outcomes[job] for job in all_jobs if job in outcomes]


def _record(job: Job, answer: dict, output_dir: str) -> Outcome:
    if "error" in answer:
        return Outcome(job, "failed", error=answer["error"])
    _write_atomically(os.path.join(output_dir, job.result), answer["json"] + "\n")
    return Outcome(job, "done", symmetries=answer["symmetries"], generators=answer["generators"],
                   continuous=answer["continuous"], vertices=answer["vertices"], seconds=answer["seconds"])


def _write_summary(output_dir: str, jobs: list[Job], outcomes: dict[Job, Outcome]) -> None:
    path = os.path.join(output_dir, SUMMARY)
    with open(path + ".tmp", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=SUMMARY_COLUMNS)
        writer.writeheader()
        for job in jobs:
            if job in outcomes:
                writer.writerow(outcomes[job].row())
    os.replace(path + ".tmp", path)


class ProgressLine:
    """`[##########..........] 12/40 meshes, 1 failed  model.ply`, redrawn in place on a
    terminal; elsewhere one line per mesh."""
    WIDTH = 30

    def __init__(self, stream=sys.stderr):
        self.stream = stream
        self.terminal = stream.isatty()
        self.failed = 0

    def __call__(self, outcome: Outcome, finished: int, total: int) -> None:
        self.failed += outcome.status == "failed"
        filled = self.WIDTH * finished // max(total, 1)
        failed = f", {self.failed} failed" if self.failed else ""
        text = f"[{'#' * filled}{'.' * (self.WIDTH - filled)}] {finished}/{total} meshes{failed}  " \
               f"{outcome.job.mesh}: {outcome.status}"
        if outcome.status == "failed":
            text += f" ({outcome.error})"
        if self.terminal:
            self.stream.write("\r\033[K" + text[:200])
            if finished == total:
                self.stream.write("\n")
        else:
            self.stream.write(text + "\n")
        self.stream.flush()
