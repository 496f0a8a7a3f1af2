"""The file protocol: a renderer without Python answers a request file, and the library
judges the answers (``docs/conformance.md`` documents the format, with a C++ answerer).

``write_request(path, reference, ...)`` writes what ``compare`` would ask: ``eval`` and
``pdf`` at pairs (each pair also reversed, for reciprocity), and ``sample`` at each view from
given uniforms. The renderer writes one answer per query. ``read_answers(answers, request)``
is then a candidate that ``compare`` judges with exactly those queries.

JSON lines (``.jsonl``): the first line is a header, ``{"format":
"adobe_bsdf.conformance.request", "version": 1, "seed": ..., "n_samples": ..., "views":
[[x, y, z], ...], "float32": false, "eval": N_EVAL, "sample": N_SAMPLE}``; then one query
a line, ``{"id": 0, "query": "eval", "wo": [x, y, z], "wi": [x, y, z]}`` or ``{"id": 7,
"query": "sample", "wo": [x, y, z], "u": [u0, u1, u2]}``. The answers, one a line in any
order: ``{"id": 0, "f": [r, g, b], "pdf": p}`` and ``{"id": 7, "wi": [x, y, z], "weight":
[r, g, b], "pdf": p, "f": [r, g, b]}`` (``f`` of a sample: eval at the sampled direction;
a grey value may be one number; a failed sample has pdf 0).

NPZ (``.npz``): the request holds ``eval_wo``, ``eval_wi``, ``sample_wo``, ``sample_u`` and
``header`` (the header's JSON); the answers ``eval_f`` ``(N_EVAL, 3)``, ``eval_pdf``,
``sample_wi``, ``sample_weight``, ``sample_pdf``, ``sample_f``, in the request's order.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from adobe_bsdf.conformance.compare import Plan, make_plan
from adobe_bsdf.validation.candidate import CandidateError

__all__ = ["write_request", "read_request", "read_answers", "answer_request",
           "AnsweredCandidate", "FORMAT"]

FORMAT, VERSION = "adobe_bsdf.conformance.request", 1


def _queries(plan: Plan):
    """(eval wo, eval wi, sample wo, sample u) of ``plan``: every pair and its reverse; the
    views' uniforms in view order."""
    eval_wo = np.concatenate([plan.wo, plan.wi])
    eval_wi = np.concatenate([plan.wi, plan.wo])
    u = np.concatenate([plan.uniforms(k) for k in range(len(plan.views))])
    sample_wo = np.repeat(plan.views, plan.n_samples, axis=0)
    return eval_wo, eval_wi, sample_wo, u


def _header(plan: Plan, n_eval: int, n_sample: int, eta) -> dict:
    return {"format": FORMAT, "version": VERSION, "seed": plan.seed,
            "n_samples": plan.n_samples, "views": plan.views.tolist(),
            "float32": plan.float32, "eta": eta, "eval": n_eval, "sample": n_sample}


def write_request(path, reference, *, views=None, n_samples: int = 100_000, seed: int = 0,
                  float32: bool = False) -> Plan:
    """Write the queries of ``compare(reference, ..., views, n_samples, seed, float32)`` to
    ``path`` (``.jsonl`` or ``.npz``); returns their ``Plan``."""
    path = Path(path)
    plan = make_plan(reference, views, n_samples, seed, float32)
    eval_wo, eval_wi, sample_wo, u = _queries(plan)
    eta = getattr(reference, "eta", None)
    header = _header(plan, len(eval_wo), len(u), None if eta is None else float(np.max(eta)))
    if path.suffix == ".npz":
        np.savez_compressed(path, eval_wo=eval_wo, eval_wi=eval_wi, sample_wo=sample_wo,
                            sample_u=u, header=np.array(json.dumps(header)))
        return plan
    if path.suffix != ".jsonl":
        raise ValueError(f"path = {str(path)!r}: allowed a .jsonl or .npz file")
    with path.open("w", encoding="utf-8") as out:
        out.write(json.dumps(header) + "\n")
        for i, (a, b) in enumerate(zip(eval_wo.tolist(), eval_wi.tolist(), strict=True)):
            out.write(f'{{"id": {i}, "query": "eval", "wo": {a}, "wi": {b}}}\n')
        first = len(eval_wo)
        for j, (a, b) in enumerate(zip(sample_wo.tolist(), u.tolist(), strict=True)):
            out.write(f'{{"id": {first + j}, "query": "sample", "wo": {a}, "u": {b}}}\n')
    return plan


def read_request(path) -> tuple[Plan, dict]:
    """The ``Plan`` of a request file and its query arrays (``eval_wo``, ``eval_wi``,
    ``sample_wo``, ``sample_u``), checked against each other (``ValueError`` naming the
    file and what differs)."""
    path = Path(path)
    if path.suffix == ".npz":
        with np.load(path) as data:
            header = json.loads(str(data["header"]))
            arrays = {k: np.asarray(data[k], dtype=np.float64) for k in (
                "eval_wo", "eval_wi", "sample_wo", "sample_u")}
    else:
        header, arrays = _read_request_lines(path)
    if header.get("format") != FORMAT or header.get("version") != VERSION:
        raise ValueError(f"{path}: not a request of {FORMAT} version {VERSION}")
    n_eval = len(arrays["eval_wo"]) // 2
    wo, wi = arrays["eval_wo"][:n_eval], arrays["eval_wi"][:n_eval]
    keep = None
    if header["float32"]:
        from adobe_bsdf.validation.mitsuba import well_conditioned

        keep = well_conditioned(wo, wi, header.get("eta"))
    plan = Plan(np.asarray(header["views"], dtype=np.float64), wo, wi, keep,
                int(header["n_samples"]), int(header["seed"]), bool(header["float32"]))
    expected = _queries(plan)
    for name, want in zip(("eval_wo", "eval_wi", "sample_wo", "sample_u"), expected,
                          strict=True):
        if arrays[name].shape != want.shape or not np.array_equal(arrays[name], want):
            raise ValueError(f"{path}: its {name} is not what its header's seed and views "
                             "give: the file was changed")
    return plan, arrays


def _read_request_lines(path: Path):
    eval_wo, eval_wi, sample_wo, sample_u = [], [], [], []
    with path.open(encoding="utf-8") as lines:
        header = _json_line(path, 1, next(lines, ""))
        for number, line in enumerate(lines, start=2):
            q = _json_line(path, number, line)
            if q.get("query") == "eval":
                eval_wo.append(q["wo"])
                eval_wi.append(q["wi"])
            else:
                sample_wo.append(q["wo"])
                sample_u.append(q["u"])
    return header, {k: np.asarray(v, dtype=np.float64).reshape(-1, 3) for k, v in (
        ("eval_wo", eval_wo), ("eval_wi", eval_wi), ("sample_wo", sample_wo),
        ("sample_u", sample_u))}


def _json_line(path, number: int, line: str) -> dict:
    try:
        value = json.loads(line)
    except json.JSONDecodeError as exc:
        raise ValueError(f"{path} line {number}: not JSON ({exc.msg}): {line[:80]!r}") from None
    if not isinstance(value, dict):
        raise ValueError(f"{path} line {number}: not a JSON object: {line[:80]!r}")
    return value


def _field(path, number, record: dict, name: str, width: int | None):
    """Field ``name`` of an answer as floats: ``width`` numbers (or one, for a grey
    colour of width 3), or one number (``width`` None)."""
    if name not in record:
        raise ValueError(f"{path} line {number}: no field {name!r}")
    value = np.asarray(record[name], dtype=np.float64) if isinstance(
        record[name], (int, float, list)) else None
    if value is None or (width is None and value.ndim != 0) or (
            width is not None and value.shape not in ((width,), ()) + (((1,),) if width
                                                                        == 3 else ())):
        raise ValueError(f"{path} line {number}: field {name!r} = {record[name]!r}: allowed "
                         + ("a number" if width is None else f"a list of {width} numbers"))
    if width == 3 and value.size == 1:
        value = np.repeat(value.reshape(1), 3)
    return value


def _read_answer_lines(path: Path, n_eval: int, n_sample: int) -> dict:
    out = {"eval_f": np.full((n_eval, 3), np.nan), "eval_pdf": np.full(n_eval, np.nan),
           "sample_wi": np.full((n_sample, 3), np.nan),
           "sample_weight": np.full((n_sample, 3), np.nan),
           "sample_pdf": np.full(n_sample, np.nan), "sample_f": np.full((n_sample, 3), np.nan)}
    seen = np.zeros(n_eval + n_sample, dtype=bool)
    with path.open(encoding="utf-8") as lines:
        for number, line in enumerate(lines, start=1):
            if not line.strip():
                continue
            record = _json_line(path, number, line)
            if record.get("format"):  # an optional header
                continue
            i = record.get("id")
            if not isinstance(i, int) or not 0 <= i < n_eval + n_sample:
                raise ValueError(f"{path} line {number}: field 'id' = {i!r}: allowed an "
                                 f"integer in [0, {n_eval + n_sample}) (the request's ids)")
            if seen[i]:
                raise ValueError(f"{path} line {number}: query {i} answered twice")
            seen[i] = True
            if i < n_eval:
                out["eval_f"][i] = _field(path, number, record, "f", 3)
                out["eval_pdf"][i] = _field(path, number, record, "pdf", None)
            else:
                j = i - n_eval
                for name, width in (("wi", 3), ("weight", 3), ("pdf", None), ("f", 3)):
                    out[f"sample_{name}"][j] = _field(path, number, record, name, width)
    missing = np.flatnonzero(~seen)
    if missing.size:
        raise ValueError(f"{path}: {missing.size} of {seen.size} queries unanswered (the "
                         f"first: id {missing[0]}); a truncated file?")
    return out


def read_answers(answers, request) -> AnsweredCandidate:
    """The candidate of an answer file to a request file (``ValueError`` naming the file,
    the line and the field of what it cannot use)."""
    plan, queries = read_request(request)
    path = Path(answers)
    n_eval, n_sample = len(queries["eval_wo"]), len(queries["sample_u"])
    if path.suffix == ".npz":
        with np.load(path) as data:
            got = {k: np.asarray(data[k], dtype=np.float64) for k in data.files}
        shapes = {"eval_f": (n_eval, 3), "eval_pdf": (n_eval,), "sample_wi": (n_sample, 3),
                  "sample_weight": (n_sample, 3), "sample_pdf": (n_sample,),
                  "sample_f": (n_sample, 3)}
        for name, shape in shapes.items():
            if name not in got:
                raise ValueError(f"{path}: no array {name!r}")
            if got[name].shape != shape:
                raise ValueError(f"{path}: array {name!r} has shape {got[name].shape}, the "
                                 f"request asks for {shape}")
    else:
        got = _read_answer_lines(path, n_eval, n_sample)
    ok = got["sample_pdf"] > 0.0
    norm = np.linalg.norm(got["sample_wi"][ok], axis=-1)
    off = np.flatnonzero(np.abs(norm - 1.0) > 1e-5)
    if off.size:
        j = int(np.flatnonzero(ok)[off[0]])
        raise ValueError(f"{path}: sample answer id {n_eval + j}: field 'wi' = "
                         f"{got['sample_wi'][j].tolist()} is off the sphere (|wi| = "
                         f"{norm[off[0]]:.6g})")
    return AnsweredCandidate(plan, queries, got, str(path))


def _keys(a, b) -> list[bytes]:
    rows = np.ascontiguousarray(np.concatenate([np.asarray(a, np.float64).reshape(-1, 3),
                                                np.asarray(b, np.float64).reshape(-1, 3)], 1))
    return [r.tobytes() for r in rows]


class AnsweredCandidate:
    """A renderer's answers to a request, as a candidate: ``eval``, ``pdf`` and ``sample``
    answer exactly the requested queries (and ``eval``, ``pdf`` the sampled directions of
    its samples, from the answers' ``f`` and ``pdf``); anything else raises
    ``CandidateError``. ``plan`` makes ``compare`` ask exactly those."""

    def __init__(self, plan: Plan, queries: dict, answers: dict, name: str):
        self.plan, self.name, self.eta = plan, name, None
        self._f = dict(zip(_keys(queries["eval_wo"], queries["eval_wi"]),
                           zip(answers["eval_f"], answers["eval_pdf"], strict=True),
                           strict=True))
        sampled = _keys(queries["sample_wo"], answers["sample_wi"])
        for key, f, pdf in zip(sampled, answers["sample_f"], answers["sample_pdf"],
                               strict=True):
            if pdf > 0.0:
                self._f.setdefault(key, (f, pdf))
        self._sample = dict(zip(_keys(queries["sample_wo"], queries["sample_u"]), zip(
            answers["sample_wi"], answers["sample_weight"], answers["sample_pdf"],
            strict=True), strict=True))

    def __repr__(self) -> str:
        return f"AnsweredCandidate({self.name!r})"

    def _lookup(self, table: dict, a, b, what: str):
        out = []
        for key in _keys(a, b):
            found = table.get(key)
            if found is None:
                row = np.frombuffer(key, np.float64)
                raise CandidateError(f"{self.name} holds no answer to {what} at "
                                     f"{row[:3].tolist()}, {row[3:].tolist()}: only the "
                                     "requested queries can be judged")
            out.append(found)
        return out

    def eval(self, wo, wi):
        shape = np.broadcast_shapes(np.shape(wo)[:-1], np.shape(wi)[:-1])
        found = self._lookup(self._f, *np.broadcast_arrays(wo, wi), "eval")
        return np.array([f for f, _ in found]).reshape(shape + (3,))

    def pdf(self, wo, wi):
        shape = np.broadcast_shapes(np.shape(wo)[:-1], np.shape(wi)[:-1])
        found = self._lookup(self._f, *np.broadcast_arrays(wo, wi), "pdf")
        return np.array([p for _, p in found]).reshape(shape)

    def sample(self, wo, u):
        shape = np.broadcast_shapes(np.shape(wo)[:-1], np.shape(u)[:-1])
        found = self._lookup(self._sample, *np.broadcast_arrays(wo, u), "sample")
        wi = np.array([x[0] for x in found]).reshape(shape + (3,))
        weight = np.array([x[1] for x in found]).reshape(shape + (3,))
        pdf = np.array([x[2] for x in found]).reshape(shape)
        return wi, weight, pdf


def answer_request(request, candidate, answers) -> Path:
    """Answer the request file ``request`` with ``candidate`` (any ``Candidate``) into
    ``answers`` (``.jsonl`` or ``.npz``), as a renderer would: what ``read_answers`` reads."""
    from adobe_bsdf.validation.candidate import as_lobe

    plan, q = read_request(request)
    lobe = as_lobe(candidate)
    f, pdf = lobe.eval(q["eval_wo"], q["eval_wi"]), lobe.pdf(q["eval_wo"], q["eval_wi"])
    s = lobe.sample(q["sample_wo"], q["sample_u"])
    sample_f = lobe.eval(q["sample_wo"], np.where(s.pdf[:, None] > 0, s.wi, q["sample_wo"]))
    arrays = {"eval_f": f, "eval_pdf": pdf, "sample_wi": s.wi, "sample_weight": s.weight,
              "sample_pdf": s.pdf, "sample_f": sample_f}
    answers = Path(answers)
    if answers.suffix == ".npz":
        np.savez_compressed(answers, **arrays)
        return answers
    n_eval = len(f)
    with answers.open("w", encoding="utf-8") as out:
        for i in range(n_eval):
            out.write(json.dumps({"id": i, "f": f[i].tolist(), "pdf": float(pdf[i])}) + "\n")
        for j in range(len(s.pdf)):
            out.write(json.dumps({"id": n_eval + j, "wi": s.wi[j].tolist(),
                                  "weight": s.weight[j].tolist(), "pdf": float(s.pdf[j]),
                                  "f": sample_f[j].tolist()}) + "\n")
    return answers
