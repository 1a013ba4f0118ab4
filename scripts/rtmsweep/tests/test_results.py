"""Unit tests of row files and results.csv: cells, row files, assembling, remote runs' folders."""

import os

from rtmsweep import columns, results

HEAD = columns.header(["loop_credits"])


def row(run_id, status="ok", **values):
    return {"run_id": run_id, "status": status, "scene": run_id.split("-")[0], **values}


def write_rows(out, *rows, head=HEAD):
    os.makedirs(results.runs_dir(out), exist_ok=True)
    for r in rows:
        results.write_row(results.row_path(out, r["run_id"]), head, r)


def test_cells():
    assert [results.cell(v) for v in (None, True, False, 3, 0.1, 1e-20, float("inf"), float("nan"), "a,b")] == \
        ["", "true", "false", "3", "0.1", "1e-20", "inf", "nan", "a,b"]


def test_csv_text_round_trips():
    rows = [row("a-1", error='rtm: "quoted", with commas', cycles=12), row("b-2", "failed", error="x\ny")]
    text = results.format_rows(HEAD, rows)
    assert text.splitlines()[0] == ",".join(HEAD)
    head, back = results.parse_csv(text)
    assert head == HEAD
    assert back[0]["error"] == 'rtm: "quoted", with commas' and back[0]["cycles"] == "12"
    assert back[1]["error"] == "x\ny" and back[1]["cycles"] == ""
    assert results.parse_csv("") == ([], [])


def test_a_row_file_is_the_header_and_one_row(tmp_path):
    path = str(tmp_path / "r.row")
    results.write_row(path, HEAD, row("a-1", cycles=5))
    head, r = results.read_row(path)
    assert head == HEAD and r["run_id"] == "a-1" and r["cycles"] == "5"
    assert os.listdir(tmp_path) == ["r.row"]  # no temporary file left


def test_results_csv_is_assembled_in_the_specs_order(tmp_path):
    out = str(tmp_path)
    write_rows(out, row("c-3"), row("a-1", "failed"), row("b-2"), row("old-9"), row("old-0"))
    rows, other = results.assemble(out, HEAD, order=["a-1", "b-2", "c-3", "d-4"])
    assert other == 0 and set(rows) == {"a-1", "b-2", "c-3", "old-9", "old-0"}
    head, back = results.read_csv(results.results_path(out))
    assert head == HEAD
    # The spec's runs in its order, then those of no longer listed configurations by run id.
    assert [r["run_id"] for r in back] == ["a-1", "b-2", "c-3", "old-0", "old-9"]
    assert back[0]["status"] == "failed"
    assert sorted(os.listdir(out)) == ["results.csv", "runs"]  # written through a rename


def test_assembling_again_gives_the_same_file(tmp_path):
    out = str(tmp_path)
    write_rows(out, row("b-2"), row("a-1"))
    results.assemble(out, HEAD, ["a-1", "b-2"])
    first = open(results.results_path(out)).read()
    results.assemble(out, HEAD, ["a-1", "b-2"])
    assert open(results.results_path(out)).read() == first


def test_no_rows_is_a_header(tmp_path):
    out = str(tmp_path)
    assert results.assemble(out, HEAD, ["a-1"]) == ({}, 0)
    assert open(results.results_path(out)).read() == ",".join(HEAD) + "\n"


def test_rows_of_other_columns_are_left_out(tmp_path):
    out = str(tmp_path)
    write_rows(out, row("a-1"))
    write_rows(out, row("x-1"), head=columns.header(["search_fifo_depth"]))
    rows, other = results.assemble(out, HEAD, ["a-1"])
    assert set(rows) == {"a-1"} and other == 1


def test_only_row_files_count(tmp_path):
    out = str(tmp_path)
    write_rows(out, row("a-1"))
    runs = results.runs_dir(out)
    for name in ("b-2.json", "b-2.err", "c-3.row.host.7.tmp", "d-4.row"):
        open(os.path.join(runs, name), "w").close()  # d-4.row: empty, not a row
    assert set(results.read_rows(out)) == {"a-1"}


def test_rows_without_a_row_file_are_found(tmp_path):
    out = str(tmp_path)
    write_rows(out, row("a-1"))
    with open(results.results_path(out), "w") as f:
        f.write(results.format_rows(HEAD, [row("a-1"), row("gone-2")]))
    assert results.orphans(out) == ["gone-2"]


def test_remote_runs_folders_are_moved_into_runs(tmp_path):
    out = str(tmp_path)
    runs = results.runs_dir(out)
    back = os.path.join(runs, "a-1.remote")
    os.makedirs(back)
    for name in ("a-1.json", "a-1.err", "a-1.png"):
        open(os.path.join(back, name), "w").close()
    results.write_row(os.path.join(back, "a-1.row"), HEAD, row("a-1"))
    unfinished = os.path.join(runs, "b-2.remote")
    os.makedirs(unfinished)
    open(os.path.join(unfinished, "b-2.err"), "w").close()  # interrupted there: no row

    assert results.collect_remote(out) == ["a-1"]
    assert sorted(os.listdir(runs)) == ["a-1.err", "a-1.json", "a-1.png", "a-1.row", "b-2.remote"]
    assert os.listdir(unfinished) == ["b-2.err"]
    assert set(results.read_rows(out)) == {"a-1"}
    assert results.collect_remote(out, ["a-1", "b-2"]) == []
