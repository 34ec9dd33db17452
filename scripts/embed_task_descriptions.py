#!/usr/bin/env python3
"""Embeds the Meta-World task descriptions for CARE-style task metadata, offline.

CARE (Sodhani, Zhang, Pineau, ICML 2021) keys attention over a mixture of state encoders with
a pretrained language model's encoding of each task's natural-language description. This
script makes those encodings from our own descriptions (data/task_descriptions/metaworld.yaml)
with WordLlama's default model (PyPI package ``wordllama``, MIT; its 256-dimensional
``l2_supercat`` token table and tokenizer ship inside the wheel, so nothing is downloaded:
the model is loaded from the package's own files with ``disable_download=True``). A description's embedding is the mean of
its token vectors (WordLlama's average pooling over the attention mask), L2-normalised.

Output: a JSON file (default data/task_descriptions/metaworld_embeddings.json) with the
package, its version, the model, the dimension, the date and, for each task in the YAML's
order, its description and embedding (floats rounded to 6 decimals), written atomically
(a temporary file in the same folder, then os.replace).

Set up once (a venv of its own, ignored by git):
    python3 -m venv .venv-embed
    .venv-embed/bin/pip install "wordllama==0.4.0.post1" pyyaml
Run:
    .venv-embed/bin/python scripts/embed_task_descriptions.py

Errors are reported as one line on stderr with exit code 2.
"""

from __future__ import annotations

import argparse
import datetime
import json
import math
import os
import pathlib
import sys
import tempfile

REPO = pathlib.Path(__file__).resolve().parents[1]
DEFAULT_INPUT = REPO / "data" / "task_descriptions" / "metaworld.yaml"
DEFAULT_OUTPUT = REPO / "data" / "task_descriptions" / "metaworld_embeddings.json"
PACKAGE = "wordllama"
MODEL = "l2_supercat"
DIM = 256


class UsageError(Exception):
    """A problem to report as one line with exit code 2."""


def read_descriptions(path: pathlib.Path) -> dict[str, str]:
    """{task id: description} from the YAML file's ``tasks`` mapping, in file order."""
    try:
        import yaml
    except ImportError as e:
        raise UsageError(f"PyYAML is not installed ({e}); pip install pyyaml") from e
    try:
        with open(path, encoding="utf-8") as f:
            doc = yaml.safe_load(f)
    except OSError as e:
        raise UsageError(f"cannot read {path}: {e.strerror}") from e
    except yaml.YAMLError as e:
        raise UsageError(f"{path} is not valid YAML: {' '.join(str(e).split())}") from e
    tasks = doc.get("tasks") if isinstance(doc, dict) else None
    if not isinstance(tasks, dict) or not tasks:
        raise UsageError(f"{path} has no non-empty 'tasks' mapping")
    out: dict[str, str] = {}
    for name, text in tasks.items():
        if not isinstance(name, str) or not isinstance(text, str) or not text.strip():
            raise UsageError(f"{path}: task {name!r} needs a non-empty string description")
        out[name] = " ".join(text.split())
    return out


def embed(texts: list[str]) -> tuple[list[list[float]], str]:
    """(unit-norm mean-pooled embeddings, package version) from the bundled WordLlama model."""
    try:
        from importlib.metadata import version

        import wordllama
        from wordllama import WordLlama
    except ImportError as e:
        raise UsageError(f"the {PACKAGE} package is not installed ({e}); "
                         f"pip install 'wordllama==0.4.0.post1'") from e
    # WordLlama 0.4.0.post1 looks for its bundled tokenizer under wordllama/tokenizer/, but the
    # wheel ships it under wordllama/tokenizers/ (beside weights/), so a plain load() would
    # fetch the tokenizer from the Hugging Face hub. Its cache layout is exactly the package's
    # (cache_dir/weights/, cache_dir/tokenizers/), so naming the package folder as the cache
    # loads both bundled files, and disable_download=True makes a missing one an error.
    bundled = pathlib.Path(wordllama.__file__).resolve().parent
    try:
        model = WordLlama.load(config=MODEL, dim=DIM, cache_dir=bundled, disable_download=True)
    except FileNotFoundError as e:
        raise UsageError(f"{PACKAGE}'s bundled weights were not found: {e}") from e
    # embed() tokenizes, averages the token vectors over the attention mask and, with
    # norm=True, divides by the L2 norm.
    vectors = model.embed(texts, norm=True, return_np=True)
    if vectors.shape != (len(texts), DIM):
        raise UsageError(f"{PACKAGE} returned shape {vectors.shape}, expected ({len(texts)}, {DIM})")
    rows = []
    for text, row in zip(texts, vectors.tolist()):
        if not all(math.isfinite(x) for x in row):
            raise UsageError(f"non-finite embedding for {text!r}")
        rows.append([round(x, 6) for x in row])
    return rows, version(PACKAGE)


def to_json(doc: dict) -> str:
    """``doc`` as JSON with one line per top-level field and one line per task."""
    lines = ["{"]
    for key, value in doc.items():
        if key != "tasks":
            lines.append(f" {json.dumps(key)}: {json.dumps(value)},")
    lines.append(' "tasks": {')
    items = list(doc["tasks"].items())
    for i, (name, entry) in enumerate(items):
        comma = "," if i + 1 < len(items) else ""
        lines.append(f"  {json.dumps(name)}: {json.dumps(entry)}{comma}")
    lines += [" }", "}"]
    return "\n".join(lines) + "\n"


def write_atomically(path: pathlib.Path, text: str) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            f.write(text)
            f.flush()
            os.fsync(f.fileno())
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except FileNotFoundError:
            pass
        raise


class OneLineParser(argparse.ArgumentParser):
    """Reports a bad command line as one line (no usage block), exit code 2."""

    def error(self, message: str):
        self.exit(2, f"embed_task_descriptions.py: {message} (see --help)\n")


def main(argv: list[str] | None = None) -> int:
    parser = OneLineParser(
        description="Embed the Meta-World task descriptions (CARE's task metadata) with "
                    "WordLlama's bundled 256-d model, offline, into a JSON file.")
    parser.add_argument("--input", type=pathlib.Path, default=DEFAULT_INPUT,
                        help="YAML file with a 'tasks' mapping {task id: description} "
                             "(default: %(default)s)")
    parser.add_argument("--output", type=pathlib.Path, default=DEFAULT_OUTPUT,
                        help="JSON file to write (default: %(default)s)")
    parser.add_argument("--date", default=None,
                        help="date to record, YYYY-MM-DD (default: today, UTC)")
    args = parser.parse_args(argv)
    try:
        if args.date is None:
            date = datetime.datetime.now(datetime.timezone.utc).date().isoformat()
        else:
            try:
                date = datetime.date.fromisoformat(args.date).isoformat()
            except ValueError as e:
                raise UsageError(f"--date {args.date!r} is not YYYY-MM-DD") from e
        descriptions = read_descriptions(args.input)
        names = list(descriptions)
        vectors, pkg_version = embed([descriptions[n] for n in names])
        doc = {
            "package": PACKAGE,
            "package_version": pkg_version,
            "model": MODEL,
            "dim": DIM,
            "pooling": "mean of token vectors over the attention mask, then L2-normalised",
            "date": date,
            "source": "data/task_descriptions/metaworld.yaml, by scripts/embed_task_descriptions.py",
            "tasks": {n: {"description": descriptions[n], "embedding": v}
                      for n, v in zip(names, vectors)},
        }
        text = to_json(doc)
        try:
            write_atomically(args.output, text)
        except OSError as e:
            raise UsageError(f"cannot write {args.output}: {e.strerror or e}") from e
    except UsageError as e:
        print(f"embed_task_descriptions.py: {e}", file=sys.stderr)
        return 2
    print(f"wrote {args.output} ({len(names)} tasks, dim {DIM}, {len(text.encode())} bytes)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
