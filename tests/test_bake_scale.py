"""Table baking at scale: the same bytes in this process, on a process pool and on a Dask
cluster; interrupted bakes resume from their finished blocks, which are trusted only when
they verify."""

import dataclasses
import json
import sys

import distributed
import numpy as np
import pytest

import adobe_bsdf.__main__ as cli
from adobe_bsdf import tables
from adobe_bsdf.tables import bake
from adobe_bsdf.tables.partial import PartialBake

#: a cheap real table: ggx_conductor on 20 x 8 nodes, 5 blocks (the last one short)
SPEC = dataclasses.replace(
    tables.spec("ggx_conductor"),
    axes=tuple(dataclasses.replace(a, n=n)
               for a, n in zip(tables.spec("ggx_conductor").axes, (20, 8), strict=True)))
N_BLOCKS = -(-20 * 8 // bake.BLOCK)


@pytest.fixture(scope="module")
def cluster():
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  host="127.0.0.1", dashboard_address=":0") as c:
        yield c


@pytest.fixture(scope="module")
def reference():
    """The table baked in this process, without partial results."""
    return bake.bake(SPEC, workers=1, progress=False)


def _meta(path):
    with np.load(path) as data:
        return json.loads(str(data["meta"]))


def _content_hash(table, path):
    tables.save(table, path)
    return _meta(path)["content_hash"]


def _same_bytes(table, reference):
    return (table.values.tobytes() == reference.values.tobytes()
            and table.errors.tobytes() == reference.errors.tobytes())


def _count_stores(monkeypatch, fail_after=None):
    """Count the blocks written to partial folders (raising KeyboardInterrupt once
    ``fail_after`` of them are written, as a Ctrl-C would)."""
    written = []
    store = PartialBake.store

    def counting(self, index, *args):
        store(self, index, *args)
        written.append(index)
        if len(written) == fail_after:
            raise KeyboardInterrupt

    monkeypatch.setattr(PartialBake, "store", counting)
    return written


def test_every_executor_bakes_the_same_bytes(cluster, reference, tmp_path):
    """1 worker in process, 2 pool processes and a 2-worker Dask cluster: identical values,
    errors and content hash (only the metadata says how)."""
    expected = _content_hash(reference, tmp_path / "one.npz")
    with bake.open_executor(workers=2) as pool:
        two = bake.bake(SPEC, progress=False, executor=pool)
    with bake.open_executor(scheduler=cluster.scheduler_address) as dask:
        on_dask = bake.bake(SPEC, progress=False, executor=dask)
    assert (reference.meta["executor"], two.meta["executor"], on_dask.meta["executor"]) == (
        "in process", "process pool", "dask")
    assert two.meta["workers"] == on_dask.meta["workers"] == 2
    for i, table in enumerate((two, on_dask)):
        assert _same_bytes(table, reference)
        assert _content_hash(table, tmp_path / f"{i}.npz") == expected


@pytest.mark.parametrize("where", ["pool", "dask"])
def test_an_interrupted_bake_resumes_with_only_the_missing_blocks(where, cluster, reference,
                                                                  tmp_path, monkeypatch,
                                                                  capsys):
    how = {"workers": 2} if where == "pool" else {"scheduler": cluster.scheduler_address}
    partial = tmp_path / "t.partial"
    written = _count_stores(monkeypatch, fail_after=2)
    with pytest.raises(KeyboardInterrupt), bake.open_executor(**how) as ex:
        bake.bake(SPEC, progress=False, executor=ex, partial=partial)
    assert sorted(p.name for p in partial.glob("block_*.npz")) == [
        f"block_{i:06d}.npz" for i in sorted(written)]
    assert f"2 of {N_BLOCKS} blocks are kept in {partial}" in capsys.readouterr().err
    written = _count_stores(monkeypatch)
    with bake.open_executor(**how) as ex:
        resumed = bake.bake(SPEC, progress=False, executor=ex, partial=partial)
    assert len(written) == N_BLOCKS - 2  # only the missing blocks were computed
    assert f"resuming with 2 of {N_BLOCKS} blocks" in capsys.readouterr().err
    assert _same_bytes(resumed, reference)


def test_a_partial_folder_of_another_declaration_is_not_trusted(reference, tmp_path,
                                                                monkeypatch, capsys):
    partial = tmp_path / "t.partial"
    other = dataclasses.replace(SPEC, order=SPEC.order - 4)
    bake.compute(other, other.grid(), workers=1, progress=False, partial=partial)
    written = _count_stores(monkeypatch)
    values, errors = bake.compute(SPEC, SPEC.grid(), workers=1, progress=False,
                                  partial=partial)
    assert len(written) == N_BLOCKS  # every block recomputed
    err = capsys.readouterr().err
    assert f"ignoring {N_BLOCKS} finished blocks in {partial}" in err and "order" in err
    assert values.tobytes() == reference.values.reshape(values.shape).tobytes()
    assert errors.tobytes() == reference.errors.reshape(errors.shape).tobytes()
    (partial / "manifest.json").unlink()  # blocks without a manifest: unknown, not trusted
    del written[:]
    bake.compute(SPEC, SPEC.grid(), workers=1, progress=False, partial=partial)
    assert len(written) == N_BLOCKS and "no readable manifest" in capsys.readouterr().err


def test_a_corrupt_block_is_recomputed(reference, tmp_path, monkeypatch, capsys):
    partial = tmp_path / "t.partial"
    bake.compute(SPEC, SPEC.grid(), workers=1, progress=False, partial=partial)
    truncated = partial / "block_000001.npz"
    truncated.write_bytes(truncated.read_bytes()[:100])  # a write cut short
    tampered = partial / "block_000003.npz"
    with np.load(tampered) as data:
        parts = dict(data)
    np.savez(tampered, **{**parts, "values": parts["values"] + 1e-12})  # loads, but wrong
    stray = partial / ".block_000002.npz.x.tmp"  # a temporary file left by a kill
    stray.write_bytes(b"junk")
    written = _count_stores(monkeypatch)
    values, _ = bake.compute(SPEC, SPEC.grid(), workers=1, progress=False, partial=partial)
    assert sorted(written) == [1, 3]
    assert capsys.readouterr().err.count("does not verify: recomputing") == 2
    assert not stray.exists()
    assert values.tobytes() == reference.values.reshape(values.shape).tobytes()


def test_bake_command_on_a_local_dask_cluster(tmp_path, capsys):
    """``bake NAME --dask-workers 2`` writes the same table as ``--workers 1``, and removes
    its partial folder once the table is saved."""
    folders = {}
    for how in (["--workers", "1"], ["--dask-workers", "2"]):
        out = tmp_path / how[0]
        code = cli.main(["bake", "ggx_conductor", "--resolution", "6", "--out", str(out),
                         *how], prog="adobe-bsdf")
        assert code == 0, capsys.readouterr().err
        assert sorted(p.name for p in out.iterdir()) == ["ggx_conductor.npz",
                                                         "ggx_conductor_avg.npz"]
        folders[how[0]] = out
    assert "computing on dask (2 workers)" in capsys.readouterr().out
    for name in ("ggx_conductor", "ggx_conductor_avg"):
        one, dask = (_meta(folder / f"{name}.npz") for folder in folders.values())
        assert one["content_hash"] == dask["content_hash"]
        assert (one["executor"], dask["executor"]) == ("in process", "dask")


def test_without_dask_the_command_says_how_to_install_it(tmp_path, capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "distributed", None)  # import distributed fails
    code = cli.main(["bake", "ggx_conductor", "--out", str(tmp_path), "--dask-workers", "2"],
                    prog="adobe-bsdf")
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1
    assert err.startswith("adobe-bsdf bake: error:") and 'pip install -e ".[dask]"' in err
