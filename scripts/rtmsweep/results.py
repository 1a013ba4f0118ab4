"""Row files and results.csv.

Each run writes its own row file, DIR/runs/RUN_ID.row (the header and its one row), written to a
temporary file and renamed into place, so a row file is always whole: a run with a row file is
done. results.csv is derived from the row files: assemble() rewrites it from them, in a fixed
order, again through a temporary file and a rename, so nothing ever appends to a shared file
and nothing needs a lock.
"""

import csv
import io
import os
import socket

RESULTS = "results.csv"
RUNS = "runs"
ROW_SUFFIX = ".row"
# --no-shared-dir: a run on another host writes its files to runs/RUN_ID.remote/, which GNU
# parallel brings back here (--return).
REMOTE_SUFFIX = ".remote"


def results_path(out):
    return os.path.join(out, RESULTS)


def runs_dir(out):
    return os.path.join(out, RUNS)


def row_path(out, run_id):
    return os.path.join(out, RUNS, run_id + ROW_SUFFIX)


# --- CSV text ----------------------------------------------------------------------------------

def cell(v):
    """A value as a CSV cell: empty for None, true/false, floats in full."""
    if v is None:
        return ""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        return repr(v) if v == v and v not in (float("inf"), float("-inf")) else str(v)
    return str(v)


def format_rows(head, rows, with_header=True):
    """CSV text of ROWS (dicts) in the columns of HEAD; a column a row lacks is empty."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    if with_header:
        w.writerow(head)
    for row in rows:
        w.writerow([cell(row.get(c)) for c in head])
    return buf.getvalue()


def parse_csv(text):
    """(header, rows as dicts) of CSV text; ([], []) when it is empty."""
    records = list(csv.reader(io.StringIO(text)))
    if not records:
        return [], []
    head = records[0]
    return head, [dict(zip(head, r)) for r in records[1:] if r]


def read_csv(path):
    """(header, rows as dicts) of a CSV file; ([], []) when it is missing or empty."""
    try:
        with open(path, newline="") as f:
            return parse_csv(f.read())
    except FileNotFoundError:
        return [], []


def write_atomic(path, text):
    """Writes PATH through a temporary file beside it and a rename: readers see the old file or
    the new one, never part of one. The temporary name is this process's own, so that sweeps on
    several hosts sharing the folder never write the same one."""
    tmp = f"{path}.{socket.gethostname()}.{os.getpid()}.tmp"
    try:
        with open(tmp, "w") as f:
            f.write(text)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        try:
            os.remove(tmp)
        except FileNotFoundError:
            pass
        raise


# --- row files ---------------------------------------------------------------------------------

def write_row(path, head, row):
    """A run's row file: HEAD and ROW."""
    write_atomic(path, format_rows(head, [row]))


def read_row(path):
    """(header, row) of a row file; (header, None) when it holds no row."""
    head, rows = read_csv(path)
    return head, (rows[0] if rows else None)


def read_rows(out):
    """Every row file in DIR/runs/: {run_id: (header, row)}."""
    found = {}
    try:
        names = sorted(os.listdir(runs_dir(out)))
    except FileNotFoundError:
        return found
    for name in names:
        if not name.endswith(ROW_SUFFIX):
            continue
        head, row = read_row(os.path.join(runs_dir(out), name))
        if row and row.get("run_id"):
            found[row["run_id"]] = (head, row)
    return found


def ordered(rows, order):
    """The rows (dicts by run id) of ORDER's run ids in that order, then any others by run id."""
    rank = {rid: i for i, rid in enumerate(order)}
    return [rows[rid] for rid in sorted(rows, key=lambda rid: (rank.get(rid, len(rank)), rid))]


def assemble(out, head, order=()):
    """Rewrites DIR/results.csv from the row files: the rows with this header, the runs of ORDER
    (the spec's job order) first, then any others (say, of PE counts the spec no longer lists)
    by run id. Returns (rows written as dicts by run id, number of row files left out because
    their columns differ).

    Several sweeps may assemble at once (shards of one spec, each at its end): after the rename
    the rows are read again, and while they differ from what was written (another sweep renamed
    an older list over this one, or a run finished meanwhile) results.csv is written again."""
    for _ in range(20):
        found = read_rows(out)
        rows = {rid: row for rid, (h, row) in found.items() if h == head}
        text = format_rows(head, ordered(rows, order))
        write_atomic(results_path(out), text)
        again = read_rows(out)
        if again == found:
            try:
                with open(results_path(out), newline="") as f:
                    if f.read() == text:
                        break
            except FileNotFoundError:
                pass
    return rows, len(found) - len(rows)


def orphans(out):
    """The run ids results.csv has a row for but DIR/runs/ has no row file of (deleted by hand?):
    assembling would drop those rows."""
    _, rows = read_csv(results_path(out))
    return [r["run_id"] for r in rows if r.get("run_id") and not os.path.exists(row_path(out, r["run_id"]))]


def collect_remote(out, run_ids=None):
    """--no-shared-dir: moves the files of each run GNU parallel brought back into
    DIR/runs/RUN_ID.remote/ to DIR/runs/, its row file last (the row says the run is done, so it
    comes when everything else is in place). RUN_IDS: only these runs. Returns the ids moved."""
    runs = runs_dir(out)
    if run_ids is None:
        try:
            run_ids = [n[:-len(REMOTE_SUFFIX)] for n in sorted(os.listdir(runs)) if n.endswith(REMOTE_SUFFIX)]
        except FileNotFoundError:
            return []
    moved = []
    for rid in run_ids:
        folder = os.path.join(runs, rid + REMOTE_SUFFIX)
        row_file = rid + ROW_SUFFIX
        if not os.path.isfile(os.path.join(folder, row_file)):
            continue  # not back (yet), or interrupted there: it has no row, a rerun runs it again
        names = sorted(os.listdir(folder), key=lambda n: n == row_file)
        for name in names:
            os.replace(os.path.join(folder, name), os.path.join(runs, name))
        os.rmdir(folder)
        moved.append(rid)
    return moved
