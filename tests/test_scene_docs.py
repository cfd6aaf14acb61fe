#!/usr/bin/python3
"""test_scene_docs.py — the scene schema, the loader and docs/scene-format.md agree.

The schema (host/setup/scene/scene_keys.def) states every key a scene may hold once: its
section, type, default, range or words and meaning; the loader reads keys through it and
`sphsolid scene-keys` prints it.  This test checks that
- the key tables of docs/scene-format.md are the schema's, section by section, and every
  section is shown (tools/scene_keys_doc.py --check);
- every key name the loader looks up by hand (config_setting_get_member with a literal, or
  a KEY_NAMES list for scene_first_member) is a key of the schema: a key read past the schema would be undocumented;
- every key in the first column of the document's other tables (those outside the
  generated blocks, e.g. the fluid state by formulation) is a key of the schema or an
  output field;
- `sphsolid scene-keys` refuses an unknown section with exit status 2.
"""
import glob
import os
import re
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sphtest import BIN, SRC, check, finish  # noqa: E402

tool = os.path.join(SRC, "tools", "scene_keys_doc.py")
out = subprocess.run(["/usr/bin/python3", tool, "--check", "--sphsolid", BIN],
                     capture_output=True, text=True)
check(out.returncode == 0, "docs/scene-format.md differs from the schema:\n" + out.stderr)

listing = subprocess.run([BIN, "scene-keys"], capture_output=True, text=True)
check(listing.returncode == 0, f"sphsolid scene-keys failed: {listing.stderr}")
schema_keys = set(re.findall(r"^\| `([^`]+)` \|", listing.stdout, re.M))
nsections = listing.stdout.count("### ")
check(len(schema_keys) > 100 and nsections > 30,
      f"the schema lists {len(schema_keys)} key names in {nsections} sections")

bad = subprocess.run([BIN, "scene-keys", "no_such_section"], capture_output=True, text=True)
check(bad.returncode == 2 and "no section 'no_such_section'" in bad.stderr,
      f"an unknown section: exit {bad.returncode}, {bad.stderr!r}")

# keys the loader reads by hand
loader = ""
for path in sorted(glob.glob(os.path.join(SRC, "host", "setup", "scene", "*.c"))):
    loader += open(path).read()
by_hand = set(re.findall(r'config_setting_get_member\(\w+, "([^"]+)"\)', loader))
for names in re.findall(r"KEY_NAMES\(([^)]*)\)", loader):
    by_hand.update(re.findall(r'"([^"]+)"', names))
check(len(by_hand) > 20, f"{len(by_hand)} keys read by hand")
unknown = sorted(by_hand - schema_keys)
check(not unknown, f"keys the loader reads that the schema does not state: {unknown}")

# the other tables of the document
doc = open(os.path.join(SRC, "docs", "scene-format.md")).read()
outside = re.sub(r"<!-- scene-keys: .*? -->.*?<!-- /scene-keys -->", "", doc, flags=re.S)
table_keys = set(re.findall(r"^\| `([a-z_][a-z0-9_]*)` \|", outside, re.M))
words = set(re.findall(r'`"([a-z_0-9-]+)"`', listing.stdout))
unknown = sorted(table_keys - schema_keys - words)
check(not unknown, f"table keys of docs/scene-format.md the schema does not know: {unknown}")
print(f"{len(schema_keys)} key names in {nsections} sections; {len(by_hand)} read by hand; "
      f"{len(table_keys)} keys in the document's own tables")
finish("test_scene_docs")
