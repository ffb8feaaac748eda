#!/usr/bin/env python3
"""Builds the seed corpora of the fuzz targets (fuzz/corpus/<target>/) from the project's own
files: every quoted value of the worked examples and exercises (syntax), the exercise and
worked-example files themselves, the answers shown in the exercise README, the book's chapters
wrapped as mdBook's [context, book] JSON, and the book's `run` commands as command lines.
Every regression input is a seed of its target too. Run from the repository root or fuzz/.
"""
import hashlib
import json
import pathlib
import re
import shlex

ROOT = pathlib.Path(__file__).resolve().parent.parent
CORPUS = ROOT / "fuzz" / "corpus"
# the order of CLI_SUBCOMMANDS in src/fuzzing.rs: the cli target's first byte picks one
SUBCOMMANDS = ["observe", "canonical", "gain", "control", "optimal", "kalman", "perfect", "exercise",
               "feedback", "discrete", "zoh", "reduced", "detectable", "dlqe", "verify", "simulate",
               "check", "grade"]


def put(target, data):
    if isinstance(data, str):
        data = data.encode()
    folder = CORPUS / target
    folder.mkdir(parents=True, exist_ok=True)
    (folder / hashlib.sha1(data).hexdigest()).write_bytes(data)


def main():
    examples = sorted((ROOT / "worked_examples").glob("*.toml"))
    exercises = sorted((ROOT / "worked_examples" / "exercises").glob("*.toml"))
    for f in examples:
        put("worked_example", f.read_bytes())
    for f in exercises:
        put("exercise", f.read_bytes())
    for f in examples + exercises:
        for value in re.findall(r'"((?:[^"\\]|\\.)*)"', f.read_text()):
            if any(ch.isdigit() for ch in value) or "s" in value:
                put("syntax", value)
    readme = (ROOT / "worked_examples" / "exercises" / "README.md").read_text()
    for block in re.findall(r"```toml\n(.*?)```", readme, re.S):
        if "[answers]" in block:
            put("answers", block)
    put("answers", '[answers]\nL = "[-6; -12]"\ndesired = "(s + 4)(s + 5)"\n')
    chapters = sorted((ROOT / "book" / "src").glob("*.md"))
    context = {"root": "book", "config": {}, "renderer": "html", "mdbook_version": "0.5.3"}
    for f in chapters:
        chapter = {"Chapter": {"name": f.stem, "content": f.read_text(), "number": None,
                               "sub_items": [], "path": f.name, "source_path": f.name,
                               "parent_names": []}}
        put("book", json.dumps([context, {"items": [chapter]}]))
        for command in re.findall(r"\{\{#owb run ([^}]*)\}\}", f.read_text()):
            args = shlex.split(command)
            if args and args[0] in SUBCOMMANDS:
                put("cli", bytes([SUBCOMMANDS.index(args[0])]) + "\n".join(args[1:]).encode())
    # one hand-written line per subcommand the book does not run
    for line in [
        'canonical --a "[2 -3; 4 -5]" --c "[-3 2]" --b "[1; 0]"',
        'control --a "[0 1; 0 0]" --b "[0; 1]" --c "[1 0]" --l "[2; 1]" --feedback-poly "s^2 + 2s + 2"',
        'control --a "[0 1; -k -c]" --b "[0; 1]" --c "[1 0]" --observer-poly "(s + 3)^2" --feedback-poly "s^2 + 2s + 2"',
        'perfect --a "[0 1; -2 -3]" --b "[0; 1]" --c "[1 0]" --changed-a "[0 1; -3 -3]"',
        'exercise new --kind pole-placement --order 3 --seed 11',
        'gain --a "[0 1 0; 0 0 1; -1 -2 -3]" --c "[1 0 0]" --butterworth 1/2 --json',
        'feedback --a "[2 -3; 4 -5]" --b "[2; 3]" --poles "-4, -5" --convention u=fx',
        'discrete --a "[2 -3; 4 -5]" --c "[-3 2]" --poles "1/2, 1/4" --estimator current --json',
        'discrete --a "[0 1; -2 -3]" --c "[1 0]" --continuous-poles "-4, -5" --period 1/10',
        'zoh --a "[0 1 0; 0 0 1; 0 0 0]" --b "[0; 0; 1]" --period 1/2',
        'reduced --a "[-2 1 0; 1 -2 1; 0 1 -2]" --c "[1 0 0; 0 0 1]" --poles "-4"',
        'detectable --a "[-1 0; 1 -1]" --c "[1 0]" --poles "-3" --json',
        'dlqe --a "[1 1/10; 0 1]" --g "[1/200; 1/10]" --c "[1 0]" --qn "[1]" --rn "[1/100]"',
        'exercise new --kind dead-beat --order 2 --student ada',
        'grade stoustrup-pole-assignment submissions --csv report.csv --feedback feedback',
        'grade variants submissions --csv report.csv --kind dead-beat --order 2 --json',
        'grade variants submissions --csv report.csv --kind reduced-order --order 3 --convention a+lc',
        'check stoustrup-pole-assignment answers.toml --json',
        'verify stoustrup-pole-assignment --derivations --json',
        'simulate baranowski-rc-ladder --scenario x0-sensitivity --json',
    ]:
        args = shlex.split(line)
        put("cli", bytes([SUBCOMMANDS.index(args[0])]) + "\n".join(args[1:]).encode())
    for target in ["syntax", "answers", "exercise", "worked_example", "book", "cli"]:
        for f in (ROOT / "fuzz" / "regressions" / target).glob("*"):
            if not f.name.startswith("."):
                put(target, f.read_bytes())
    for target in sorted(p.name for p in CORPUS.iterdir()):
        print(target, len(list((CORPUS / target).iterdir())), "seeds")


if __name__ == "__main__":
    main()
