#!/usr/bin/python3
"""scene_keys_doc.py — write (or check) the key tables of docs/scene-format.md.

The scene schema (host/setup/scene/scene_keys.def) states every key of a scene once:
section, name, type, default, range or words, meaning.  docs/scene-format.md shows each
section's keys as a table between the lines

    <!-- scene-keys: SECTION -->
    <!-- /scene-keys -->

and this script fills them with `sphsolid scene-keys SECTION`.  With --check it writes
nothing and exits 1 naming every section whose table differs from the schema, every
section of the schema the document does not show, and every block naming a section the
schema does not have (test_scene_docs runs it so).

usage: tools/scene_keys_doc.py [--check] [--sphsolid PATH] [--doc PATH]
"""
import argparse
import os
import re
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BLOCK = re.compile(r"(<!-- scene-keys: ([^ ]*) -->\n)(.*?)(<!-- /scene-keys -->)", re.S)


def schema_table(sphsolid, section):
    out = subprocess.run([sphsolid, "scene-keys", section], capture_output=True, text=True)
    if out.returncode != 0:
        return None
    return out.stdout


def schema_sections(sphsolid):
    out = subprocess.run([sphsolid, "scene-keys", "-"], capture_output=True, text=True)
    # the refusal lists the sections: ... the sections: "" "resolution" ...
    return re.findall(r'"([^"]*)"', out.stderr.split("the sections:", 1)[1])


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--check", action="store_true", help="compare only; exit 1 on a difference")
    ap.add_argument("--sphsolid", default=os.environ.get(
        "SPHSOLID_BIN", os.path.join(ROOT, "build", "sphsolid")))
    ap.add_argument("--doc", default=os.path.join(ROOT, "docs", "scene-format.md"))
    args = ap.parse_args()
    doc = open(args.doc).read()
    problems = []
    shown = []

    def fill(m):
        section = m.group(2).strip('"')
        shown.append(section)
        table = schema_table(args.sphsolid, section)
        if table is None:
            problems.append(f"block for section '{section}': the schema has no such section")
            return m.group(0)
        if m.group(3) != table:
            problems.append(f"section '{section}': the table differs from the schema")
        return m.group(1) + table + m.group(4)

    new = BLOCK.sub(fill, doc)
    for section in schema_sections(args.sphsolid):
        if shown.count(section) != 1:
            problems.append(f"section '{section}' of the schema is shown {shown.count(section)} "
                            f"times in {os.path.relpath(args.doc, ROOT)} (expected once)")
    if args.check:
        for p in problems:
            print(f"{os.path.relpath(args.doc, ROOT)}: {p}", file=sys.stderr)
        if problems:
            print("run tools/scene_keys_doc.py to rewrite the tables from the schema",
                  file=sys.stderr)
        return 1 if problems else 0
    if new != doc:
        open(args.doc, "w").write(new)
    missing = [p for p in problems if "differs" not in p]
    for p in missing:
        print(p, file=sys.stderr)
    return 1 if missing else 0


if __name__ == "__main__":
    sys.exit(main())
