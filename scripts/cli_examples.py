#!/usr/bin/env python3
"""Runs the example sessions of docs/cli.md and says where the program's output has drifted from
what the page shows (or, with --update, rewrites the page with what it prints now).

    scripts/cli_examples.py [--cli build/tools/areamatch] [--shared ../shared] [--doc docs/cli.md] [--update] [--all]

An example session is a fenced block of `$ command` lines, each followed by its expected output
(stdout, then stderr; eval's `[i/n]` progress lines left out). In the expected output:
- `...` on a line of its own stands for any number of lines (one per command);
- times are not compared: every `N ms`, the stage times of `segment`, the per-step times of
  `merge` and the time columns of eval's table are masked on both sides.
Commands run one by one with bash in one scratch folder (so one block can use what another
wrote), where `maps` points at SHARED/maps and `../shared` means SHARED; `areamatch` is the
program under test; `echo $?` prints the previous command's exit status. An HTML comment right
before a block steers it: `<!-- cli-example: setup CMD -->` runs CMD first (output not shown),
`<!-- cli-example: slow -->` runs it only with --all. Needs SHARED (blocks naming `maps/` or
`../shared` are the documented real-map examples); exits 77 (skipped) without it.
Numbers quoted in the page's prose with three or more decimals (an example's p_correct, say) must
be ones that an example or a command's --help prints now, and the README's counts of the shared
pairs must be those that `eval ../shared/pairs.json` prints, and every option a command's --help
lists must be named in the page's section of that command: each is reported (not rewritten by
--update).
Exit status: 0 all examples as shown, 1 drift (a diff per command, or a stale number), 2 usage.
"""

import argparse
import difflib
import functools
import os
import pathlib
import re
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parents[1]
SKIP = 77

# What differs from run to run: times.
MASKS = [
    (re.compile(r"\d+(\.\d+)? ms\b"), "<t> ms"),
    (re.compile(r"\b(binarize|boundary|skeleton|rooms|areas) \d+\.\d+"), r"\1 <t>"),
    (re.compile(r"\((prepare) \d+, (match) \d+, (fuse) \d+\)"), r"(\1 <t>, \2 <t>, \3 <t>)"),
    # eval's table: name, areas src/dst, then four times (seg src, seg dst, match, total).
    (re.compile(r"^(\S+ \d+/\d+) \d+\.\d+ \d+\.\d+ \d+\.\d+ \d+\.\d+"), r"\1 <times>"),
    (re.compile(r"(median|mean) \d+(\.\d+)? ms"), r"\1 <t> ms"),
]
PROGRESS = re.compile(r"^\[\d+/\d+\] ")
# A number with three or more decimals in the prose quotes a program's output (defaults and rules
# of thumb have fewer): it must be one that the examples print now, or a default that --help prints.
QUOTED_NUMBER = re.compile(r"(?<![\w.])\d+\.\d{3,}(?![\w.])")


def mask(line):
    # Columns are padded to their widest value, which is often a time: compare words, not spaces.
    line = re.sub(r"\s+", " ", line.strip())
    for pattern, replacement in MASKS:
        line = pattern.sub(replacement, line)
    return line.rstrip()


class Command:
    def __init__(self, text, line_no):
        self.text = text          # without the "$ "
        self.line_no = line_no    # 0-based line of the "$ " line in the page
        self.expected = []        # expected output lines


class Block:
    def __init__(self, start, end, commands, setup, slow):
        self.start, self.end = start, end  # lines of the opening and closing fences
        self.commands, self.setup, self.slow = commands, setup, slow


def parse(lines):
    blocks, i = [], 0
    while i < len(lines):
        if lines[i].strip() == "```":
            j = i + 1
            while j < len(lines) and lines[j].strip() != "```":
                j += 1
            body = lines[i + 1:j]
            if body and body[0].startswith("$ "):
                commands = []
                for k, line in enumerate(body):
                    if line.startswith("$ "):
                        commands.append(Command(line[2:], i + 1 + k))
                    else:
                        commands[-1].expected.append(line)
                setup, slow = [], False
                back = i - 1
                while back >= 0 and (lines[back].startswith("<!-- cli-example:") or not lines[back].strip()):
                    m = re.match(r"<!-- cli-example: (setup (.*)|slow) -->", lines[back].strip())
                    if m and m.group(2):
                        setup.insert(0, m.group(2))
                    elif m:
                        slow = True
                    back -= 1
                blocks.append(Block(i, j, commands, setup, slow))
            i = j + 1
        else:
            i += 1
    return blocks


def run(command, cli, shared, cwd, previous_status):
    if command.strip() == "echo $?":
        return str(previous_status) + "\n", previous_status
    text = re.sub(r"(^|\s)areamatch\s", lambda m: f"{m.group(1)}{cli} ", command, count=1)
    text = text.replace("../shared", str(shared))
    done = subprocess.run(["bash", "-c", text], cwd=cwd, capture_output=True, text=True)
    err = "".join(l for l in done.stderr.splitlines(True) if not PROGRESS.match(l))
    return done.stdout + err, done.returncode


def matches(expected, actual):
    """Whether actual lines fit the expected ones (with at most one '...'), times masked."""
    e = [mask(l) for l in expected]
    a = [mask(l) for l in actual]
    if "..." in e:
        k = e.index("...")
        head, tail = e[:k], e[k + 1:]
        return len(a) >= len(head) + len(tail) and a[:len(head)] == head and a[len(a) - len(tail):] == tail
    return a == e


def updated(expected, actual):
    """The expected lines rewritten from the actual output, keeping a '...' elision."""
    if "..." in expected:
        k = expected.index("...")
        head, tail = len(expected[:k]), len(expected) - k - 1
        if len(actual) >= head + tail:
            return actual[:head] + ["..."] + (actual[len(actual) - tail:] if tail else [])
    return actual


def prose_lines(lines):
    """(0-based line, text) of every line outside fenced blocks."""
    inside = False
    for i, line in enumerate(lines):
        if line.strip().startswith("```"):
            inside = not inside
        elif not inside:
            yield i, line


def stale_prose_numbers(doc, lines, printed):
    """The prose's quoted numbers that nothing printed (`printed`: the examples' and --help's text)."""
    known = set(QUOTED_NUMBER.findall(printed))
    return [f"{doc}:{i + 1}: {number} is quoted but no example or --help prints it now"
            for i, line in prose_lines(lines) for number in QUOTED_NUMBER.findall(line) if number not in known]


@functools.lru_cache(maxsize=None)
def command_help(cli, shared, command):
    """(text, status) of `areamatch COMMAND --help`, run once per command."""
    return run(f"areamatch {command} --help", cli, shared, ".", 0)


def undocumented_options(doc, text, cli, shared):
    """The options a command's --help lists that its `## command` section of the page never names."""
    sections = {}
    for section in re.split(r"^## ", text, flags=re.M)[1:]:
        command = section.split("\n", 1)[0].strip()
        if re.fullmatch(r"[a-z]+", command):
            sections[command] = section

    def named(command, option, seen=()):
        """Whether the section names the option, itself or through the options it refers to."""
        section = sections.get(command, "")
        if re.search(re.escape(option) + r"(?![a-z-])", section):
            return True
        # "and match's options", "the options of `simulate`": those sections name the rest.
        for other in set(re.findall(r"(\w+)'s options|the options of `(\w+)`", section)):
            other = "".join(other)
            if other in sections and other not in seen and named(other, option, seen + (command,)):
                return True
        # "[map options]": how a map file is read, the options of `info`.
        return "map options" in section and command != "info" and named("info", option, seen + (command,))

    problems = []
    for command in sections:
        help_text, status = command_help(cli, shared, command)
        if status != 0:
            continue
        for option in sorted(set(re.findall(r"^\s+(--[a-z][a-z-]*)", help_text, re.M))):
            if not named(command, option):
                problems.append(f"{doc}: `## {command}` does not name {option} (its --help does)")
    return problems


def stale_readme_counts(readme, printed):
    """The README's counts of the shared pairs against `eval`'s summary line as printed now."""
    summary = re.search(r"^correct: (\d+) / (\d+) \(", printed, re.M)  # eval's summary: accepted and right
    if not summary or not readme.exists():
        return []
    accepted, total = summary.groups()
    text = re.sub(r"\s+", " ", readme.read_text())
    problems = []
    for pattern, want, what in [(r"on the (\d+) real pairs of `\.\./shared/pairs\.json`", total, "real pairs"),
                                (r"(\d+) of the \d+ true pairs accepted", accepted, "accepted pairs"),
                                (r"\d+ of the (\d+) true pairs accepted", total, "true pairs")]:
        for found in re.findall(pattern, text):
            if found != want:
                problems.append(f"{readme}: says {found} {what}, `eval ../shared/pairs.json` prints {want}")
    return problems


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--cli", default=str(ROOT / "build" / "tools" / "areamatch"))
    parser.add_argument("--shared", default=os.environ.get("AREAMATCH_SHARED_DIR", str(ROOT.parent / "shared")))
    parser.add_argument("--doc", default=str(ROOT / "docs" / "cli.md"))
    parser.add_argument("--update", action="store_true", help="rewrite the page with today's output")
    parser.add_argument("--all", action="store_true", help="also the blocks marked slow")
    args = parser.parse_args()

    cli, shared, doc = pathlib.Path(args.cli).resolve(), pathlib.Path(args.shared).resolve(), pathlib.Path(args.doc)
    if not cli.exists():
        print(f"cli_examples: no program at {cli} (build it, or give --cli)", file=sys.stderr)
        return 2
    if not (shared / "maps").is_dir():
        print(f"cli_examples: skipped: no shared maps at {shared}", file=sys.stderr)
        return SKIP
    lines = doc.read_text().split("\n")
    drift, checked = 0, 0
    blocks = parse(lines)
    printed = []  # everything the examples and --help print, for the prose's quoted numbers
    for command in sorted(set(re.findall(r"^\$ areamatch (\w+)", doc.read_text(), re.M))):
        printed.append(command_help(cli, shared, command)[0])
    with tempfile.TemporaryDirectory(prefix="cli_examples_") as scratch:
        os.symlink(shared / "maps", pathlib.Path(scratch) / "maps")
        for block in blocks:
            if block.slow and not args.all:
                continue
            for setup in block.setup:
                run(setup, cli, shared, scratch, 0)
            status = 0
            for command in block.commands:
                output, status = run(command.text, cli, shared, scratch, status)
                actual = output.rstrip("\n").split("\n") if output.strip() else []
                printed.append(output)
                checked += 1
                if matches(command.expected, actual):
                    continue
                drift += 1
                print(f"{doc}:{command.line_no + 1}: $ {command.text}")
                sys.stdout.writelines(difflib.unified_diff([l + "\n" for l in command.expected], [l + "\n" for l in actual],
                                                           "shown", "printed now"))
                command.expected[:] = updated(command.expected, actual)
    if args.update and drift:
        # The page again, each command line followed by its (updated) output.
        commands = {c.line_no: c for block in blocks for c in block.commands}
        out, i = [], 0
        while i < len(lines):
            out.append(lines[i])
            i += 1
            if i - 1 in commands:
                out.extend(commands[i - 1].expected)
                while i < len(lines) and not lines[i].startswith("$ ") and lines[i].strip() != "```":
                    i += 1
        doc.write_text("\n".join(out))
        print(f"cli_examples: rewrote {drift} outputs in {doc}")
    print(f"cli_examples: {checked - drift} of {checked} example commands print what {doc.name} shows")
    # Numbers quoted in the prose drift with the program as examples do (and are not rewritten by
    # --update: a sentence around a number may need more than a new number).
    stale = stale_prose_numbers(doc, lines, "\n".join(printed))
    stale += undocumented_options(doc, "\n".join(lines), cli, shared)
    if doc.resolve() == (ROOT / "docs" / "cli.md").resolve():
        stale += stale_readme_counts(ROOT / "README.md", "\n".join(printed))
    for problem in stale:
        print(problem)
    print(f"cli_examples: {len(stale)} quoted numbers no longer printed or options not documented")
    return 1 if (drift and not args.update) or stale else 0


if __name__ == "__main__":
    sys.exit(main())
