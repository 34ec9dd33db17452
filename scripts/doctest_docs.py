#!/usr/bin/env python3
"""Runs the commands shown with their output in README.md and docs/ and compares the output.

A shown output is a ```console block: lines starting with `$ ` are commands (a line ending in
`\\` continues on the next), the lines after a command up to the next `$ ` line are its output
(trailing blank lines dropped). Each block runs in a fresh scratch directory holding links to the
repository's configs/, docs/, python/ and scripts/, with `build/manyworlds` and `manyworlds` (on
PATH) pointing at --cli; commands run with bash, and their output is stdout followed by stderr
(the exit status is not compared). Comparison, line by line:

  - a shown line `...` (indentation aside) stands for any number of lines, none included;
  - runs of spaces compare equal to one space, and trailing spaces are ignored;
  - every number compares exactly, as text, unless a marker says otherwise.

Markers are HTML comments on the lines right above a block (GitHub does not show them), several
allowed:

  <!-- doctest: skip (REASON) -->   not run; the reason is required
  <!-- doctest: slow -->            run only with --blocks slow or all (more than ~10 s)
  <!-- doctest: timing -->          numbers with a time or rate unit are not compared: a number
                                    with a k/M/G suffix (398k, 8.00M), or followed by ns, us, ms,
                                    s or a rate "WORDS/s" (38.7 frames/s)
  <!-- doctest: tolerance 5% -->    every number may differ from the shown one by 5% (relative)
  <!-- doctest: needs torch -->     skipped (and said so) when the program lacks that part:
                                    torch (train/eval), mujoco (the manipulation envs), render

A block that shows `$ ` lines but is not a console block is an error, as is a console block
without a command or a marker that is not one of the above: the docs cannot show output
that escapes the test. Exit status 0 when every block run matched, 1 otherwise, 2 on bad use.

Examples:
  scripts/doctest_docs.py --cli build/manyworlds                  # every block
  scripts/doctest_docs.py --cli build/manyworlds --blocks fast    # what ctest's quick suite runs
  scripts/doctest_docs.py --list                                  # the blocks and their markers
  scripts/doctest_docs.py --cli build/manyworlds docs/envs.md    # one page (FILE:LINE: one block)
"""

from __future__ import annotations

import argparse
import difflib
import glob
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from typing import Dict, List, Optional, Sequence, Tuple

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
LINKED = ["configs", "docs", "python", "scripts", "examples"]
MARKER = re.compile(r"^\s*<!--\s*doctest:\s*(.*?)\s*-->\s*$")
FENCE = re.compile(r"^(\s*)(`{3,})(.*)$")
# A number, with its SI suffix (398k, 8.00M) where it has one.
NUMBER = re.compile(r"[-+]?(?:\d+\.\d+|\d+|\.\d+)(?:[eE][-+]?\d+)?(?:[kMG](?![A-Za-z0-9]))?")
SUFFIX = {"k": 1e3, "M": 1e6, "G": 1e9}
# What may follow a number measured in time or rate (the `timing` marker).
# (a number with an SI suffix counts as timing too).
TIMING_UNIT = re.compile(r"\s?(?:ns|us|µs|ms|s|min)(?![A-Za-z0-9])|\s?[A-Za-z][A-Za-z ]*/s(?![A-Za-z0-9])")
NEEDS = ("torch", "mujoco", "render")


@dataclass
class Command:
    line: int            # 1-based line of the `$ ` in the file
    text: str            # the command, continuation lines joined with newlines
    expected: List[str]  # the shown output


@dataclass
class Block:
    path: str
    line: int            # 1-based line of the opening fence
    end: int             # 1-based line of the closing fence
    commands: List[Command]
    skip: Optional[str] = None
    slow: bool = False
    timing: bool = False
    tolerance: Optional[float] = None
    needs: List[str] = field(default_factory=list)

    @property
    def where(self) -> str:
        return f"{os.path.relpath(self.path, REPO)}:{self.line}"


class DocError(Exception):
    pass


def doc_files() -> List[str]:
    files = [os.path.join(REPO, "README.md")]
    files += sorted(glob.glob(os.path.join(REPO, "docs", "**", "*.md"), recursive=True))
    return files


def parse_markers(lines: Sequence[str], fence_index: int, where: str) -> Dict[str, object]:
    """The doctest markers on the lines right above the fence (blank lines between allowed)."""
    markers: Dict[str, object] = {"needs": []}
    i = fence_index - 1
    while i >= 0 and (not lines[i].strip() or MARKER.match(lines[i])):
        m = MARKER.match(lines[i])
        i -= 1
        if not m:
            continue
        text = m.group(1)
        if text.startswith("skip"):
            reason = re.fullmatch(r"skip\s*\((.+)\)", text)
            if not reason:
                raise DocError(f"{where}: 'doctest: skip' needs a reason: skip (REASON)")
            markers["skip"] = reason.group(1).strip()
        elif text == "slow":
            markers["slow"] = True
        elif text == "timing":
            markers["timing"] = True
        elif re.fullmatch(r"tolerance\s+\d+(\.\d+)?%", text):
            markers["tolerance"] = float(text.split()[1][:-1]) / 100.0
        elif re.fullmatch(r"needs\s+\w+", text) and text.split()[1] in NEEDS:
            markers["needs"].append(text.split()[1])  # type: ignore[union-attr]
        else:
            raise DocError(f"{where}: unknown doctest marker '{text}' (skip (REASON), slow, "
                           f"timing, tolerance N%, needs {'|'.join(NEEDS)})")
    return markers


def parse_commands(body: List[str], first_line: int, where: str) -> List[Command]:
    commands: List[Command] = []
    i = 0
    while i < len(body):
        line = body[i]
        if line.startswith("$ "):
            start = first_line + i
            parts = [line[2:]]
            while parts[-1].endswith("\\") and i + 1 < len(body):
                i += 1
                parts.append(body[i])
            commands.append(Command(start, "\n".join(parts), []))
        elif commands:
            commands[-1].expected.append(line)
        elif line.strip():
            raise DocError(f"{where}: a console block starts with '$ COMMAND', not '{line[:40]}'")
        i += 1
    for command in commands:
        while command.expected and not command.expected[-1].strip():
            command.expected.pop()
    if not commands:
        raise DocError(f"{where}: a console block without a '$ ' command")
    return commands


def parse_file(path: str) -> List[Block]:
    lines = open(path, encoding="utf-8").read().split("\n")
    rel = os.path.relpath(path, REPO)
    blocks: List[Block] = []
    i = 0
    while i < len(lines):
        m = FENCE.match(lines[i])
        if not m:
            i += 1
            continue
        indent, ticks, info = m.groups()
        j = i + 1
        while j < len(lines) and not re.match(r"^\s*" + ticks + r"\s*$", lines[j]):
            j += 1
        body = [l[len(indent):] if l.startswith(indent) else l.lstrip() for l in lines[i + 1:j]]
        where = f"{rel}:{i + 1}"
        language = info.strip().split()[0] if info.strip() else ""
        if language == "console":
            markers = parse_markers(lines, i, where)
            blocks.append(Block(path, i + 1, j + 1, parse_commands(body, i + 2, where),
                                skip=markers.get("skip"), slow=bool(markers.get("slow")),
                                timing=bool(markers.get("timing")),
                                tolerance=markers.get("tolerance"),
                                needs=list(markers["needs"])))  # type: ignore[arg-type]
        elif any(l.startswith("$ ") for l in body):
            raise DocError(f"{where}: a '{language or 'plain'}' block shows '$ ' commands; "
                           "make it a ```console block (scripts/doctest_docs.py --help)")
        i = j + 1
    return blocks


# ---- comparison -------------------------------------------------------------------------------

def split_numbers(line: str) -> Tuple[List[str], List[Tuple[str, str]]]:
    """The text between numbers (spaces collapsed) and each number with the text after it."""
    texts, numbers = [], []
    last = 0
    for m in NUMBER.finditer(line):
        # a number glued to a word (mt10, v3, x86) is text, not a number
        if m.start() > 0 and (line[m.start() - 1].isalpha() or line[m.start() - 1] == "_"):
            continue
        texts.append(line[last:m.start()])
        numbers.append((m.group(0), line[m.end():]))
        last = m.end()
    texts.append(line[last:])
    return [re.sub(r"\s+", " ", t) for t in texts], numbers


def value(number: str) -> float:
    if number[-1] in SUFFIX:
        return float(number[:-1]) * SUFFIX[number[-1]]
    return float(number)


def line_matches(shown: str, actual: str, block: Block) -> bool:
    shown, actual = shown.rstrip(), actual.rstrip()
    if shown == actual:
        return True
    shown_texts, shown_numbers = split_numbers(shown)
    actual_texts, actual_numbers = split_numbers(actual)
    if len(shown_numbers) != len(actual_numbers):
        return False
    if shown_texts != actual_texts:
        return False
    for (a, after_a), (b, _) in zip(shown_numbers, actual_numbers):
        if a == b:
            continue
        if block.timing and (a[-1] in SUFFIX or TIMING_UNIT.match(after_a)):
            continue
        if block.tolerance is not None:
            x, y = value(a), value(b)
            if abs(x - y) <= block.tolerance * max(abs(x), abs(y)):
                continue
        return False
    return True


def output_matches(shown: List[str], actual: List[str], block: Block) -> bool:
    """Whether the output matches the shown lines, a `...` line standing for any lines."""
    memo: Dict[Tuple[int, int], bool] = {}

    def match(i: int, j: int) -> bool:
        key = (i, j)
        if key in memo:
            return memo[key]
        if i == len(shown):
            result = j == len(actual)
        elif shown[i].strip() == "...":
            result = any(match(i + 1, k) for k in range(j, len(actual) + 1))
        else:
            result = j < len(actual) and line_matches(shown[i], actual[j], block) and match(i + 1, j + 1)
        memo[key] = result
        return result

    sys.setrecursionlimit(max(sys.getrecursionlimit(), 4 * (len(shown) + len(actual)) + 1000))
    return match(0, 0)


# ---- running ----------------------------------------------------------------------------------

def program_parts(cli: str) -> Dict[str, bool]:
    help_text = subprocess.run([cli, "--help"], capture_output=True, text=True).stdout
    envs = subprocess.run([cli, "envs"], capture_output=True, text=True).stdout
    commands = set(re.findall(r"^\s{2}(\S+)\s", help_text, re.M))
    mujoco = re.search(r"^reach\s", envs, re.M) is not None
    return {"torch": "train" in commands, "render": "render" in commands and mujoco, "mujoco": mujoco}


def make_scratch(cli: str) -> str:
    scratch = tempfile.mkdtemp(prefix="mw-doctest-")
    for name in LINKED:
        if os.path.exists(os.path.join(REPO, name)):
            os.symlink(os.path.join(REPO, name), os.path.join(scratch, name))
    for folder in ("build", "bin"):
        os.makedirs(os.path.join(scratch, folder))
        os.symlink(cli, os.path.join(scratch, folder, "manyworlds"))
    return scratch


def run_command(command: Command, scratch: str, timeout: float) -> List[str]:
    env = dict(os.environ)
    env["PATH"] = os.path.join(scratch, "bin") + os.pathsep + env.get("PATH", "")
    env.pop("MANYWORLDS_PROGRESS", None)
    try:
        run = subprocess.run(["bash", "-c", command.text], cwd=scratch, env=env,
                             stdin=subprocess.DEVNULL, capture_output=True, text=True,
                             timeout=timeout)
        out = run.stdout + run.stderr
    except subprocess.TimeoutExpired:
        out = f"<timed out after {timeout:.0f} s>\n"
    lines = out.split("\n")
    while lines and not lines[-1].strip():
        lines.pop()
    return lines


def select(blocks: List[Block], wanted: Sequence[str]) -> List[Block]:
    """Blocks of the named files; FILE:LINE names the block that holds that line."""
    if not wanted:
        return blocks
    chosen = []
    for item in wanted:
        path, _, line = item.partition(":")
        path = os.path.abspath(path)
        hits = [b for b in blocks if os.path.abspath(b.path) == path
                and (not line or b.line <= int(line) <= b.end)]
        if not hits:
            raise DocError(f"no console block at {item}")
        chosen += [b for b in hits if b not in chosen]
    return chosen


def main(argv: Optional[Sequence[str]] = None) -> int:
    parser = argparse.ArgumentParser(
        description=__doc__.split("\n")[0],
        epilog="\n".join(__doc__.split("\n")[1:]),
        formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("where", nargs="*", help="FILE or FILE:LINE (default: README.md, docs/**/*.md)")
    parser.add_argument("--cli", default=os.path.join(REPO, "build", "manyworlds"),
                        help="the manyworlds program to run (default: build/manyworlds)")
    parser.add_argument("--blocks", choices=("fast", "slow", "all"), default="all",
                        help="fast: blocks not marked slow; slow: only those; all (default)")
    parser.add_argument("--timeout", type=float, default=600, help="seconds per command (600)")
    parser.add_argument("--list", action="store_true", help="list the blocks and exit")
    args = parser.parse_args(argv)

    try:
        blocks = [b for path in doc_files() for b in parse_file(path)]
        blocks = select(blocks, args.where)
    except DocError as e:
        print(f"doctest_docs: {e}", file=sys.stderr)
        return 2

    if args.list:
        for b in blocks:
            marks = ([f"skip ({b.skip})"] if b.skip else []) + (["slow"] if b.slow else []) + \
                (["timing"] if b.timing else []) + \
                ([f"tolerance {b.tolerance:.0%}"] if b.tolerance is not None else []) + \
                [f"needs {n}" for n in b.needs]
            print(f"{b.where}: {len(b.commands)} command(s)" + (f" [{', '.join(marks)}]" if marks else ""))
        return 0

    cli = os.path.abspath(args.cli)
    if not os.access(cli, os.X_OK):
        print(f"doctest_docs: no program at {cli} (--cli)", file=sys.stderr)
        return 2
    parts = program_parts(cli)
    failed = ran = skipped = 0
    for block in blocks:
        if args.blocks == "fast" and block.slow or args.blocks == "slow" and not block.slow:
            continue
        if block.skip:
            print(f"skip {block.where}: {block.skip}")
            skipped += 1
            continue
        missing = [n for n in block.needs if not parts[n]]
        if missing:
            print(f"skip {block.where}: the program has no {', '.join(missing)}")
            skipped += 1
            continue
        scratch = make_scratch(cli)
        try:
            for command in block.commands:
                start = time.monotonic()
                actual = run_command(command, scratch, args.timeout)
                seconds = time.monotonic() - start
                ran += 1
                rel = os.path.relpath(block.path, REPO)
                if output_matches(command.expected, actual, block):
                    print(f"ok   {rel}:{command.line} ({seconds:.1f} s): $ {command.text.splitlines()[0]}")
                    continue
                failed += 1
                print(f"FAIL {rel}:{command.line} ({seconds:.1f} s): $ {command.text}")
                diff = difflib.unified_diff(command.expected, actual, "shown", "actual", lineterm="")
                print("\n".join("     " + d for d in diff))
        finally:
            shutil.rmtree(scratch, ignore_errors=True)
    print(f"doctest_docs: {ran} commands run, {failed} failed, {skipped} blocks skipped")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
