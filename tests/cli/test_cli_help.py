#!/usr/bin/env python3
"""Every command's --help, the commands taken from the usage itself.

Usage: test_cli_help.py FIRMAMENT

`firmament --help` lists the commands (its "firmament NAME ..." lines); each command's --help lists
its subcommands the same way ("firmament batch plan ..." in `firmament batch --help`).  Each of
them answers --help and -h, first after it and after other arguments, with its usage on stdout,
nothing on stderr and exit 0, nothing written; `firmament help NAME` prints the same; its usage is
the line that lists it; and a usage error that quotes the usage quotes that same line (one source
for both).
"""
import os
import re
import subprocess
import sys
import tempfile

FIRMAMENT = os.path.abspath(sys.argv[1])
# the floor: what the listing must find at least (else a broken listing would test nothing)
KNOWN = {"render", "sun", "compare", "info", "options", "serve", "batch", "batch plan", "batch run",
         "batch slurm", "batch summary"}

checks = failures = 0


def check(ok, what):
    global checks, failures
    checks += 1
    if not ok:
        failures += 1
        print("FAIL:", what)


def run(args, cwd):
    p = subprocess.run([FIRMAMENT] + args, cwd=cwd, capture_output=True, text=True, timeout=60,
                       stdin=subprocess.DEVNULL)
    return p.returncode, p.stdout, p.stderr


def usage_lines(help_text):
    """The usage lines at the top of a help, each joined with its continuations, spaces collapsed."""
    lines = []
    for line in help_text.split("\n\n")[0].splitlines():
        words = line.split()
        if words[:1] == ["usage:"]:
            words = words[1:]
        if words[:1] == ["firmament"]:
            lines.append(words)
        elif lines:
            lines[-1] += words
    return [" ".join(w) for w in lines]


def commands_in(help_text, parent):
    """{NAME: usage line} of the commands the usage block lists below parent ([] for the top)."""
    out = {}
    for line in usage_lines(help_text):
        words = line.split()[1:]
        if words[:len(parent)] == parent and len(words) > len(parent) and re.fullmatch(r"[a-z]+", words[len(parent)]):
            out[" ".join(words[:len(parent) + 1])] = line
    return out


with tempfile.TemporaryDirectory() as work:
    top = {}
    for flag in ("--help", "-h"):
        rc, out, err = run([flag], work)
        check(rc == 0 and out.startswith("usage: firmament ") and err == "",
              f"firmament {flag}: exit {rc}, stderr {err!r}, stdout begins {out[:40]!r}")
        top = commands_in(out, [])
    todo, seen = list(top.items()), {}
    while todo:
        name, listed = todo.pop(0)
        seen[name] = listed
        words = name.split()
        for flag in ("--help", "-h"):
            rc, out, err = run(words + [flag], work)
            check(rc == 0 and err == "", f"{name} {flag}: exit {rc}, stderr {err!r}")
            check(out.startswith("usage: firmament " + name + " "), f"{name} {flag}: no usage line: {out[:80]!r}")
            check(os.listdir(work) == [], f"{name} {flag} wrote {os.listdir(work)}")
            own = commands_in(out, words)
            if own:  # a command of subcommands: its line names them, its help gives their usage
                names = listed.split()[len(words) + 1].split("|")
                check(sorted(names) == sorted(n.split()[-1] for n in own),
                      f"{name} {flag}: {listed!r} names other subcommands than {sorted(own)}")
            else:  # its usage is the line that listed it
                check(listed in usage_lines(out), f"{name} {flag}: {usage_lines(out)} is not {listed!r}")
            todo += [(sub, line) for sub, line in own.items() if sub not in seen]
        # `firmament help NAME` prints the same text as `NAME --help`
        rc, out_help, err = run(["help"] + words, work)
        check(rc == 0 and err == "" and out_help == run(words + ["--help"], work)[1],
              f"help {name}: exit {rc}, stderr {err!r}, not the text of {name} --help")
        # --help after other arguments still answers with the usage, and writes nothing
        rc, out, err = run(words + ["-o", "x.jsonl", "A.exr", "--help"], work)
        check(rc == 0 and out.startswith("usage: firmament " + name + " ") and err == "",
              f"{name} ... --help: exit {rc}, stderr {err!r}")
        check(os.listdir(work) == [], f"{name} ... --help wrote {os.listdir(work)}")
        # a usage error quotes the same usage; run only where the synopsis has a required part
        synopsis = re.sub(r"\[[^][]*(\[[^][]*\][^][]*)*\]|\(.*\)|\.\.\.", "", listed.split(None, 1 + len(words))[-1])
        if synopsis.strip():
            rc, out, err = run(words, work)
            quoted = re.search(r"usage: (firmament .*)", err)
            check(rc == 2, f"{name} without arguments: exit {rc}")
            check(not quoted or " ".join(quoted.group(1).split()) == listed,
                  f"{name}: the error's usage {quoted and quoted.group(1)!r} is not its --help's {listed!r}")
    check(KNOWN <= set(seen), f"the usage lists {sorted(seen)}, not all of {sorted(KNOWN)}")
    # an unknown command is still an error, asked either way
    for args in (["fly", "--help"], ["help", "fly"]):
        rc, out, err = run(args, work)
        check(rc == 2 and out == "" and err.count("\n") == 1, f"{' '.join(args)}: exit {rc}, stderr {err!r}")

print(f"commands: {', '.join(sorted(seen))}")
print(f"{checks} checks passed, {failures} failed" if failures else f"{checks} checks passed")
sys.exit(failures != 0)
