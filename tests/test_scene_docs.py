#!/usr/bin/python3
"""test_scene_docs.py — every key and keyword the scene loader accepts is documented.

The loader (host/setup/scene.c) states the keys of each group, and the words of each keyword
value, once, as KEYS("...", ...) lists: check_keys refuses the rest, get_keyword matches the
words.  Every such name must appear in docs/scene-format.md, as `name`, `"name"`, "name" or
as a `name = ...` assignment of a code example: a key added to the loader without a line in
the key reference fails here.  It also checks the reverse for the table rows: every key in
the first column of a table row of docs/scene-format.md that looks like a scene key (a
lower-case `name`) is one the loader knows, or one of the documented output fields,
formulation names and similar words (KEYS lists hold those too).
"""
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sphtest import SRC, check, finish  # noqa: E402

loader = open(os.path.join(SRC, "host", "setup", "scene.c")).read()
names = set()
for m in re.finditer(r"KEYS\(([^)]*)\)", loader):
    names.update(re.findall(r'"([^"]+)"', m.group(1)))
names -= {"a", "b"}  # the example in the macro's comment
doc = open(os.path.join(SRC, "docs", "scene-format.md")).read()
documented = set(re.findall(r'`"?([A-Za-z_][A-Za-z0-9_+-]*)"?`', doc))
documented |= set(re.findall(r'"([A-Za-z_][A-Za-z0-9_+-]*)"', doc))
documented |= set(re.findall(r"\b([a-z_][a-z0-9_]*) = ", doc))
missing = sorted(names - documented)
check(len(names) > 100 and not missing,
      f"{len(names)} loader names; not in docs/scene-format.md: {missing}")

# table rows whose first cell is a `key`: known to the loader (or a documented value word)
table_keys = set(re.findall(r"^\| `([a-z_][a-z0-9_]*)` \|", doc, re.M))
output_fields = set(re.findall(r'"([a-z_]+)"', loader[loader.index("OUTPUT_FIELD_NAMES"):
                                                      loader.index("OUTPUT_FIELD_NAMES") + 400]))
unknown = sorted(table_keys - names - output_fields)
check(not unknown, f"table keys of docs/scene-format.md the loader does not know: {unknown}")
print(f"{len(names)} loader names documented; {len(table_keys)} table keys known")
finish("test_scene_docs")
