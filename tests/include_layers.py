#!/usr/bin/env python3
"""No include from a lower layer to a higher one (docs/architecture.md, "Layers").

The layer order is the order of the rows of the layer table in docs/architecture.md, lowest
first: that table is the one place it is written. Every `#include "fretbem/X/..."` in
src/L/, include/fretbem/L/ and python/ must name a layer X at or below L; every folder of
src/ and include/fretbem/ must be a row of the table.

usage: include_layers.py SOURCE_DIR   (exit 1 listing each upward include)
"""
import pathlib
import re
import sys

TABLE_ROW = re.compile(r"^\|\s*`([a-z_]+)/`\s*\|")
INCLUDE = re.compile(r'^\s*#\s*include\s+"fretbem/([a-z_]+)/')


def layer_order(architecture_md):
    """The folders of the layer table, lowest first."""
    rows = [TABLE_ROW.match(line) for line in architecture_md.read_text().splitlines()]
    return [m.group(1) for m in rows if m]


def files_by_layer(root):
    """(layer, path) of every C++ source and header of the library, the CLI and python/."""
    for base in (root / "src", root / "include" / "fretbem"):
        for path in sorted(base.rglob("*")):
            if path.suffix in (".cpp", ".hpp", ".h"):
                yield path.relative_to(base).parts[0], path
    for path in sorted((root / "python").rglob("*")):
        if path.suffix in (".cpp", ".hpp", ".h"):
            yield "python", path


def violations(root, order):
    rank = {name: i for i, name in enumerate(order)}
    found = []
    for layer, path in files_by_layer(root):
        where = path.relative_to(root)
        if layer not in rank:
            found.append(f"{where}: folder {layer}/ is not a row of the layer table")
            continue
        for n, line in enumerate(path.read_text(errors="replace").splitlines(), 1):
            m = INCLUDE.match(line)
            if not m:
                continue
            target = m.group(1)
            if target not in rank:
                found.append(f"{where}:{n}: includes {target}/, not a row of the layer table")
            elif rank[target] > rank[layer]:
                found.append(f"{where}:{n}: {layer}/ includes {target}/, a higher layer")
    return found


def main():
    root = pathlib.Path(sys.argv[1])
    order = layer_order(root / "docs" / "architecture.md")
    if len(order) < 2:
        print("docs/architecture.md: no layer table found (rows | `folder/` | ... |)")
        return 1
    found = violations(root, order)
    for v in found:
        print(v)
    print(f"layers, lowest first: {' < '.join(order)}; {len(found)} violation(s)")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
