"""Shared helpers for the figure scripts: reading the harness's CSV, provenance labels,
saving figures, the common command line and one plot style.

The harness writes CSV as:  `# key: value` lines (provenance), a header, rows.
"""
import argparse
import os
import sys
import tempfile
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # figures are files; never open a window (CI and GPU boxes have no display)
import matplotlib.pyplot as plt  # noqa: E402  (must follow the backend choice)
import pandas as pd  # noqa: E402

REPO = Path(__file__).resolve().parents[1]

# One look for every figure. DejaVu ships with matplotlib, so the output is the same everywhere;
# TrueType (42) fonts keep the PDF text selectable and editable.
STYLE = {
    "font.family": "DejaVu Sans",
    "font.size": 9,
    "axes.titlesize": 10,
    "axes.labelsize": 9,
    "legend.fontsize": 8,
    "xtick.labelsize": 8,
    "ytick.labelsize": 8,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "axes.spines.top": False,
    "axes.spines.right": False,
    "savefig.dpi": 200,
    "savefig.bbox": "tight",
    "pdf.fonttype": 42,
}
# A scene keeps its colour across figures.
SCENE_COLOURS = {"armadillo": "#1f77b4", "bunny": "#d95f02"}
FOOTER_SIZE = 7


class ResultsError(Exception):
    """A results folder or file is missing or malformed; the message is one sentence for the user."""


def apply_style():
    plt.rcParams.update(STYLE)


def read_comment_block(path):
    """({key: value}, its line count) of a harness CSV's leading comment block ("# key: value"
    lines; the count, not the keys, says where the table starts)."""
    meta, lines = {}, 0
    with open(path, encoding="utf-8") as f:
        for line in f:
            if not line.startswith("#"):
                break
            key, _, value = line[1:].partition(":")
            meta[key.strip()] = value.strip()
            lines += 1
    return meta, lines


def read_csv_with_metadata(path):
    """Returns (DataFrame, {key: value}) for a harness CSV file."""
    path = Path(path)
    if not path.is_file():
        raise ResultsError(f"{path} does not exist.")
    meta, n_comment = read_comment_block(path)
    # Skip the comment block by count rather than comment='#': the writer quotes cells holding
    # '#', and a data row must never be cut short at one.
    try:
        df = pd.read_csv(path, skiprows=n_comment)
    except (pd.errors.EmptyDataError, pd.errors.ParserError) as e:
        raise ResultsError(f"{path} is not a readable CSV file ({str(e).strip().rstrip('.')}).") from None
    df.attrs["path"], df.attrs["meta"] = str(path), meta
    return df, meta


def require_columns(df, columns, path=None):
    missing = [c for c in columns if c not in df.columns]
    if missing:
        where = path or df.attrs.get("path", "the CSV file")
        raise ResultsError(f"{where} lacks the column(s) {', '.join(missing)}.")


def load_experiment(folder, experiment=None):
    """Returns (runs, metadata, {run_id: steps}) for one results/NAME folder."""
    runs, meta = load_runs(folder, experiment)
    folder = Path(_shown(folder))
    steps = {}
    for _, run in runs.iterrows():
        name = run.get("steps_file")
        name = f"{run['run_id']}_steps.csv" if pd.isna(name) or name == "" else str(name)
        path = folder / name
        if not path.is_file():
            raise ResultsError(f"{path}, the step file of run {run['run_id']}, is missing.")
        steps[run["run_id"]] = read_csv_with_metadata(path)[0]
    return runs, meta, steps


def load_runs(folder, experiment=None):
    """Returns (runs, metadata) for one results/NAME folder, without reading step files
    (for figures drawn from runs.csv alone, whose spec may not record steps)."""
    folder = Path(_shown(folder))  # errors name the path as the user would type it
    if not folder.is_dir():
        hint = f"; run `make {experiment}` first, or pass --results DIR" if experiment else ""
        raise ResultsError(f"There is no results folder at {folder}{hint}.")
    runs_path = folder / "runs.csv"
    if not runs_path.is_file():
        raise ResultsError(f"{runs_path} is missing, so {folder} holds no finished run; run the experiment again.")
    runs, meta = read_csv_with_metadata(runs_path)
    require_columns(runs, ["run_id"], runs_path)
    if runs.empty:
        raise ResultsError(f"{runs_path} holds no runs.")
    runs["run_id"] = runs["run_id"].astype(str)  # ids like "0" must not turn into ints
    return runs, meta


def _gpu(runs, meta):
    # Prefer what the runs saw; the file-level metadata is a fallback for older files.
    names = []
    if "device" in runs.columns:
        # Results of commit 400b46a have a GPU index, not a name, in this column (a column
        # name clash since fixed): skip bare numbers and use the metadata.
        names = [str(d) for d in runs["device"].dropna().unique() if not str(d).strip().isdigit()]
    if not names:
        names = [(meta.get("devices") or meta.get("cuda", "")).split(" | ")[0] or "unknown device"]
    parts = []
    for name in names:  # "A; A" (one run on two GPUs) reads better as "2 x A"
        devs = [d.strip() for d in name.split(";") if d.strip()]
        parts.append(f"{len(devs)} x {devs[0]}" if len(devs) > 1 and len(set(devs)) == 1 else "; ".join(devs))
    label = " + ".join(parts)
    return "host CPU" if label in ("host", "none", "") else label


def is_reduced(meta):
    return meta.get("reduced_scale", "no").strip().lower() in ("yes", "true", "1")


def provenance_label(meta, runs=None):
    """One line saying where the numbers came from: device, backend, scale, commit."""
    runs = runs if runs is not None else pd.DataFrame()
    backend = meta.get("backend") or (
        ", ".join(map(str, runs["backend"].dropna().unique())) if "backend" in runs.columns else "unknown")
    parts = [_gpu(runs, meta), f"{backend} backend", f"scale {meta.get('scale', 'unknown')}"]
    if is_reduced(meta):
        parts.append("REDUCED SCALE on the host backend")
    commit = meta.get("git_commit", "unknown")
    dirty = meta.get("git_dirty", "unknown").lower()
    flag = {"dirty": " (dirty)", "yes": " (dirty)", "true": " (dirty)",
            "clean": "", "no": "", "false": ""}.get(dirty, " (dirty?)")
    parts.append(f"commit {commit[:7] if commit != 'unknown' else commit}{flag}")
    if meta.get("date"):
        parts.append(meta["date"])
    return " | ".join(parts)


def add_footer(fig, text, alert=False):
    """Provenance under the axes, so a figure never travels without it."""
    fig.text(0.01, 0.005, text, fontsize=FOOTER_SIZE, ha="left", va="bottom", wrap=True,
             color="#b00000" if alert else "#555555")


def save_figure(fig, name, out_dir="plots/out", description=""):
    """Writes NAME.png and NAME.pdf; each appears only when complete (temp file, then rename)."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    written = []
    for fmt in ("png", "pdf"):
        final = out_dir / f"{name}.{fmt}"
        fd, tmp = tempfile.mkstemp(prefix=f".{name}.", suffix=f".{fmt}.tmp", dir=out_dir)
        os.close(fd)
        # No creation date, so re-plotting the same CSV gives the same PDF bytes.
        md = {"Description": description} if fmt == "png" else {"Subject": description, "CreationDate": None}
        try:
            fig.savefig(tmp, format=fmt, metadata=md)
            os.chmod(tmp, 0o666 & ~_umask())  # mkstemp makes 0600; give the usual permissions
            os.replace(tmp, final)
        except BaseException:
            Path(tmp).unlink(missing_ok=True)
            raise
        written.append(final)
        print(f"wrote {_shown(final)}")
    return written


def _umask():
    mask = os.umask(0)
    os.umask(mask)
    return mask


def _shown(path):
    # Relative to where the user stands when that is shorter; absolute otherwise.
    rel = os.path.relpath(path)
    return rel if not rel.startswith("..") else str(path)


def parse_args(name, description, argv=None, experiment=None):
    """The command line every figure script shares: --results DIR and --out DIR.
    experiment: the results folder's name when it is not the script's (several figures, one experiment)."""
    p = argparse.ArgumentParser(prog=f"{name}.py", description=description)
    experiment = experiment or name
    # Defaults are anchored at the repository, so the scripts work from any directory.
    p.add_argument("--results", type=Path, default=REPO / "results" / experiment,
                   help=f"results folder written by `sphbench run` (default: results/{experiment})")
    p.add_argument("--out", type=Path, default=REPO / "plots" / "out",
                   help="where NAME.png and NAME.pdf go (default: plots/out)")
    return p.parse_args(argv)


def column(df, name, default):
    """df[name], or `default` in every row where the harness did not write that column."""
    return df[name] if name in df.columns else pd.Series(default, index=df.index)


def as_bool(values):
    """A column of true/false (as the harness writes it, or as pandas parsed it) as booleans."""
    return values.map(lambda v: str(v).strip().lower() in ("true", "1", "1.0", "yes", "on"))


def size_label(n):
    """1034000 -> '1034K', 29800 -> '29.8K': how the paper names its scene sizes."""
    if n is None or pd.isna(n):
        return ""
    n = float(n)
    return f"{n / 1e6:.4g}M" if n >= 1e7 else f"{n / 1e3:.4g}K" if n >= 1e3 else f"{n:.0f}"


def scene_labels(runs):
    """'armadillo 1034K' per run: the scene and its requested size (set.particles, else particles)."""
    size = column(runs, "set.particles", None)
    if size.isna().all():
        size = column(runs, "particles", None)
    return pd.Series([f"{s} {size_label(n)}".strip() for s, n in zip(runs["scene"], size)], index=runs.index)


def main_guard(name, main):
    """Runs main(); a ResultsError becomes one sentence on stderr and exit code 2, not a traceback."""
    try:
        sys.exit(main())
    except ResultsError as e:
        print(f"{name}: {e}", file=sys.stderr)
        sys.exit(2)
