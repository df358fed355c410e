"""Lines of a fleet's laser logs with Ray Data: read every log of some folders (MCAP, or
Parquet tables of scans from `laserlines convert LOG scans.parquet`), extract the lines of
every scan with laserlines (one Extractor per worker), and write them as Parquet.

    python examples/ray_fleet.py LOGS... -o lines/ [--algorithm hough-split] [--param KEY=VALUE]
    python examples/ray_fleet.py s3://fleet/logs/ -o s3://fleet/lines/ --address auto

On one machine it starts a local Ray; with --address (or RAY_ADDRESS) it joins a cluster,
where Ray Data reads the files on every node, runs the extractors in an actor pool across the
cluster and writes the table in parts. Nothing here is specific to one machine: paths may be
any filesystem pyarrow reaches (local, s3://, gs://, hdfs://); every node needs the laserlines
wheel (`pip install laserlines`, or a runtime_env with it).

The output is the lines table of `laserlines extract -o lines.parquet` (one row per line:
scan, stamp, pose, end points, r, alpha, beams, rms, covariance) plus `path`, the log it came
from, and `topic`, the MCAP topic of its scan (null for Parquet input: one laser per table).
Without --topic every LaserScan topic is read, each laser's lines in its own frame: tell them
apart by `topic`. For Parquet input `scan` is the scan's index in its log, as the CLI numbers
it; MCAP messages are numbered within each batch (use `path`, `topic` and `stamp` to tell
scans apart) and have no pose (poses come from other messages of the log).

The output folder must be new or empty (a second run into it would add its files to the
first's); logs that give no line leave it without files, and the run says so.
"""

import argparse
import pathlib
import sys

import pyarrow as pa
import pyarrow.compute as pc
import pyarrow.fs as pafs
import ray
import ray.data

import laserlines

#: The schema names of LaserScan messages laserlines decodes (read_mcap filters on them).
LASERSCAN_TYPES = {"sensor_msgs/msg/LaserScan", "sensor_msgs/LaserScan", "foxglove.LaserScan"}


def log_files(inputs):
    """The MCAP and Parquet files of the inputs (files, or folders searched recursively);
    URIs (s3://...) are passed on as they are, sorted by extension."""
    mcap, parquet = [], []
    for item in inputs:
        path = pathlib.Path(item)
        if "://" not in item and not path.exists():
            raise SystemExit(f"{item}: no such file or folder")
        if "://" not in item and path.is_dir():
            mcap += sorted(str(p) for p in path.rglob("*.mcap"))
            parquet += sorted(str(p) for p in path.rglob("*.parquet"))
        elif item.endswith(".mcap"):
            mcap.append(item)
        elif item.endswith(".parquet"):
            parquet.append(item)
        else:
            raise SystemExit(f"{item}: expected a folder, an .mcap or a .parquet file")
    return mcap, parquet


def scans_datasets(mcap, parquet, topic=None):
    """One Ray dataset per kind of input: MCAP messages (rows of LaserScan messages, of
    `topic` or of every topic) and Parquet scans (rows of the scans table), each with the path
    of its log."""
    datasets = []
    if mcap:
        datasets.append(
            ray.data.read_mcap(
                mcap,
                topics={topic} if topic else None,
                message_types=LASERSCAN_TYPES,
                include_metadata=True,
                include_paths=True,
            )
        )
    if parquet:
        datasets.append(ray.data.read_parquet(parquet, include_paths=True))
    return datasets


class ExtractLines:
    """The map_batches function: one laserlines Extractor per Ray worker, kept for every batch
    that worker gets (its working memory is reused)."""

    def __init__(self, algorithm="hough-split", params=None):
        self.extractor = laserlines.Extractor(algorithm, **(params or {}))

    def __call__(self, batch: pa.Table) -> pa.Table:
        if "data" in batch.column_names:  # MCAP messages, decoded in Rust
            lines = self.extractor.extract_messages(batch)
        else:  # a batch may hold the rows of several files: number the scans by row
            scans = batch.drop_columns([c for c in ["scan"] if c in batch.column_names])
            lines = self.extractor.extract_table(scans)
        rows = lines["scan"]  # the row of each line's scan in the batch
        if "scan" in batch.column_names:  # the scan's index in its log, as the CLI has it
            lines = lines.set_column(0, lines.schema.field("scan"), pc.take(batch["scan"], rows))
        lines = lines.append_column("path", pc.take(batch["path"], rows))
        if "topic" in batch.column_names:
            topic = pc.take(batch["topic"], rows).cast(pa.string())
        else:
            topic = pa.nulls(lines.num_rows, pa.string())
        return lines.append_column("topic", topic)


def extract_lines(datasets, algorithm="hough-split", params=None, workers=None):
    """The lines of every scan of the datasets, as one dataset: the datasets joined, each
    block a batch (a block holds rows of one kind of log), an actor pool of extractors."""
    ds = datasets[0].union(*datasets[1:]) if len(datasets) > 1 else datasets[0]
    return ds.map_batches(
        ExtractLines,
        fn_constructor_kwargs={"algorithm": algorithm, "params": params},
        batch_format="pyarrow",
        batch_size=None,
        compute=ray.data.ActorPoolStrategy(min_size=1, max_size=workers),
    )


def count_paths(batch: pa.Table) -> pa.Table:
    """Rows of each path in a batch."""
    counts = pc.value_counts(batch["path"])
    return pa.table({"path": counts.field("values"), "scans": counts.field("counts")})


def scans_per_log(datasets):
    """The number of scans of each log, {path: count}: one more pass over the logs, counted
    batch by batch (no shuffle)."""
    counts = {}
    for ds in datasets:
        per_batch = ds.select_columns(["path"]).map_batches(count_paths, batch_format="pyarrow")
        for row in per_batch.iter_rows():
            counts[row["path"]] = counts.get(row["path"], 0) + row["scans"]
    return counts


def folder(output):
    """The filesystem and path of the output folder (a local path or a URI)."""
    if "://" in output:
        return pafs.FileSystem.from_uri(output)
    return pafs.LocalFileSystem(), str(pathlib.Path(output).absolute())


def check_output(output):
    """The output folder must be new or empty: the files of an earlier run would be read as
    this one's."""
    fs, path = folder(output)
    info = fs.get_file_info(path)
    if info.type == pafs.FileType.NotFound:
        return
    if info.type != pafs.FileType.Directory:
        raise SystemExit(f"{output}: not a folder")
    if fs.get_file_info(pafs.FileSelector(path, recursive=False)):
        raise SystemExit(f"{output}: not empty (its files would be read with this run's): give a new -o, or remove it")


def parse_param(text):
    key, _, value = text.partition("=")
    for kind in (int, float):
        try:
            return key, kind(value)
        except ValueError:
            pass
    return key, {"true": True, "false": False}.get(value, value)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("inputs", nargs="+", help="folders or files: .mcap, .parquet (scans)")
    p.add_argument("-o", "--output", required=True, help="folder for the lines table")
    p.add_argument("--topic", help="the MCAP topic of the scans (default: every LaserScan topic)")
    p.add_argument("--algorithm", default="hough-split", choices=laserlines.ALGORITHMS)
    p.add_argument("--param", action="append", default=[], help="KEY=VALUE, as Extractor(**params)")
    p.add_argument("--workers", type=int, help="extractors at most (default: as Ray sees fit)")
    p.add_argument("--address", help="a Ray cluster to join (default: RAY_ADDRESS, else local)")
    p.add_argument("--num-cpus", type=int, help="CPUs of the local Ray (no --address)")
    p.add_argument("--count-scans", action="store_true", help="print the scans of each log")
    args = p.parse_args(argv)

    check_output(args.output)
    ray.init(address=args.address, num_cpus=None if args.address else args.num_cpus)
    mcap, parquet = log_files(args.inputs)
    if not mcap and not parquet:
        raise SystemExit("no .mcap or .parquet file in the inputs")
    params = dict(parse_param(t) for t in args.param)
    laserlines.Extractor(args.algorithm, **params)  # bad parameters fail here, not on a worker
    datasets = scans_datasets(mcap, parquet, args.topic)
    if args.count_scans:
        for path, n in sorted(scans_per_log(datasets).items()):
            print(f"{path}: {n} scans", file=sys.stderr)
    lines = extract_lines(datasets, args.algorithm, params, args.workers)
    lines.write_parquet(args.output)
    logs = f"{len(mcap)} MCAP and {len(parquet)} Parquet logs"
    fs, path = folder(args.output)
    # Ray writes no file for no rows (and may not make the folder).
    missing = fs.get_file_info(path).type == pafs.FileType.NotFound
    if missing or not fs.get_file_info(pafs.FileSelector(path, recursive=True)):
        print(f"{logs}: no lines, nothing written to {args.output}", file=sys.stderr)
        return
    written = ray.data.read_parquet(args.output).count()
    print(f"{logs}: {written} lines in {args.output}", file=sys.stderr)


if __name__ == "__main__":
    main()
