#!/usr/bin/python3
"""Measured height maps: x3p (ISO 25178-72) and .npz files made here with Python's
stdlib zipfile + xml.etree (as SurfaceTopography's x3p reader is tested) and numpy, loaded by
`fretbem surface SCENARIO --out FILE.npy` and compared with the arrays they were made from;
plus the files that must be refused, each with one line on stderr and exit status 2.

usage: test_height_map_files.py FRETBEM_BINARY SOURCE_DIR
"""
import hashlib
import os
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET
import zipfile

import numpy as np

FRETBEM = os.path.abspath(sys.argv[1])
NX, NY, DX = 6, 4, 1e-6
FAILURES = []
rng = np.random.default_rng(7)
Z = rng.normal(scale=1e-7, size=(NY, NX))  # Z[j, i] = z(x_i, y_j)


def check(cond, what):
    if not cond:
        FAILURES.append(what)
        print("FAIL:", what)


def main_xml(nx, ny, dx, dy, dtype, md5, zinc=None, link="bindata/data.bin"):
    root = ET.Element("p:ISO5436_2", {"xmlns:p": "http://www.opengps.eu/2008/ISO5436_2"})
    r1 = ET.SubElement(root, "Record1")
    ET.SubElement(r1, "Revision").text = "ISO5436 - 2000"
    ET.SubElement(r1, "FeatureType").text = "SUR"
    axes = ET.SubElement(r1, "Axes")
    for name, inc in (("CX", dx), ("CY", dy), ("CZ", zinc)):
        a = ET.SubElement(axes, name)
        ET.SubElement(a, "AxisType").text = "I" if name != "CZ" else "A"
        ET.SubElement(a, "DataType").text = dtype if name == "CZ" else "D"
        if inc is not None:
            ET.SubElement(a, "Increment").text = repr(inc)
        ET.SubElement(a, "Offset").text = "0"
    r3 = ET.SubElement(root, "Record3")
    dim = ET.SubElement(r3, "MatrixDimension")
    for k, v in (("SizeX", nx), ("SizeY", ny), ("SizeZ", 1)):
        ET.SubElement(dim, k).text = str(v)
    dl = ET.SubElement(r3, "DataLink")
    ET.SubElement(dl, "PointDataLink").text = link
    ET.SubElement(dl, "MD5ChecksumPointData").text = md5
    r4 = ET.SubElement(root, "Record4")
    ET.SubElement(r4, "ChecksumFile").text = "md5checksum.hex"
    return ET.tostring(root, encoding="utf-8", xml_declaration=True)


def write_x3p(path, z=Z, dtype="D", dx=DX, dy=DX, zinc=None, size=None, md5=None,
              prolog=b"", extra=None, link="bindata/data.bin"):
    fmt = {"D": "<f8", "F": "<f4", "I": "<i2", "L": "<i4"}[dtype]
    data = np.ascontiguousarray(z).astype(fmt).tobytes()  # C order [y][x]: x fastest
    ny, nx = size or z.shape
    xml = main_xml(nx, ny, dx, dy, dtype, md5 or hashlib.md5(data).hexdigest(), zinc, link)
    if prolog:
        xml = xml.replace(b"?>", b"?>" + prolog, 1)
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as zf:
        zf.writestr("main.xml", xml)
        zf.writestr("bindata/data.bin", data)
        zf.writestr("md5checksum.hex", hashlib.md5(xml).hexdigest() + " *main.xml\n")
        for name, content in (extra or {}).items():
            zf.writestr(name, content)


def run(tmp, surface_file, extra_keys="", length=NX * DX, nx=NX, ny=NY):
    ini = os.path.join(tmp, "s.ini")
    with open(ini, "w") as f:
        f.write(f"[material]\nE = 1e11\nnu = 0.3\n[grid]\nnx = {nx}\nny = {ny}\n"
                f"length = {length!r}\n[surface]\ntype = file\nfile = {surface_file}\n"
                f"{extra_keys}\n[load]\nnormal_force = 1\n")
    out = os.path.join(tmp, "out.npy")
    if os.path.exists(out):
        os.remove(out)
    p = subprocess.run([FRETBEM, "surface", ini, "--out", out], capture_output=True, text=True)
    return p, (np.load(out) if p.returncode == 0 else None)


def expect_ok(tmp, name, expected, **kw):
    p, z = run(tmp, name, **kw)
    check(p.returncode == 0, f"{name}: exit {p.returncode}: {p.stderr.strip()}")
    if z is not None:
        check(z.shape == expected.shape and np.allclose(z, expected, rtol=1e-6, atol=0),
              f"{name}: values")


def expect_refused(tmp, name, needle, **kw):
    p, _ = run(tmp, name, **kw)
    err = p.stderr.strip()
    if os.environ.get("SHOW"): print(name, "->", err)
    check(p.returncode == 2, f"{name}: exit {p.returncode} (expected 2): {err}")
    check(needle in err and len(err.splitlines()) == 1 and name in err,
          f"{name}: message '{err}' lacks '{needle}' or the file name")


with tempfile.TemporaryDirectory() as t:
    os.chdir(t)
    # Good x3p files: float64, float32, int16 with a z increment (profilometer counts).
    write_x3p("d.x3p")
    expect_ok(t, "d.x3p", Z)
    write_x3p("f.x3p", dtype="F")
    expect_ok(t, "f.x3p", Z.astype(np.float32).astype(float))
    counts = np.round(Z / 1e-9)
    write_x3p("i.x3p", z=counts, dtype="I", zinc=1e-9)
    expect_ok(t, "i.x3p", counts * 1e-9)
    # The spacing comes from the file: grid.length / nx must agree, never a rescale.
    expect_refused(t, "d.x3p", "spacing along x", length=2 * NX * DX)
    write_x3p("dy.x3p", dy=2 * DX)
    expect_refused(t, "dy.x3p", "spacing along y")
    # Bad files.
    write_x3p("slip.x3p", extra={"../../evil.txt": b"x"})
    expect_refused(t, "slip.x3p", "path traversal")
    write_x3p("link.x3p", link="../data.bin")
    expect_refused(t, "link.x3p", "path traversal")
    write_x3p("dtd.x3p", prolog=b'<!DOCTYPE r [<!ENTITY a "aaaa">]>')
    expect_refused(t, "dtd.x3p", "DTD")
    write_x3p("md5.x3p", md5="0" * 32)
    expect_refused(t, "md5.x3p", "MD5")
    write_x3p("size.x3p", size=(NY, NX + 1))
    expect_refused(t, "size.x3p", "bytes")
    write_x3p("huge.x3p", size=(1 << 20, 1 << 20))
    expect_refused(t, "huge.x3p", "too large")
    with open("notzip.x3p", "wb") as f:
        f.write(b"\x00" * 100)
    expect_refused(t, "notzip.x3p", "zip")
    # .npz: one array, or the one named by surface.dataset.
    np.savez("one.npz", heights=Z)
    expect_ok(t, "one.npz", Z)
    np.savez_compressed("two.npz", a=Z, b=2 * Z)
    expect_refused(t, "two.npz", "surface.dataset")
    expect_ok(t, "two.npz", 2 * Z, extra_keys="dataset = b")
    # A 'spacing' entry is metadata, not a map: checked against grid.length / nx as x3p's is.
    np.savez("spaced.npz", heights=Z, spacing=np.float64(DX))
    expect_ok(t, "spaced.npz", Z)
    np.savez("misspaced.npz", heights=Z, spacing=np.float64(2 * DX))
    expect_refused(t, "misspaced.npz", "spacing along x")
    # A .npy carries none: surface.spacing states it, and is checked the same way.
    np.save("plain.npy", Z)
    expect_ok(t, "plain.npy", Z, extra_keys=f"spacing = {DX!r}")
    expect_refused(t, "plain.npy", "surface.spacing", extra_keys=f"spacing = {2 * DX!r}")
    # surface.layout: a non-square map stored x-first is refused loudly under the default yx,
    # and read right with layout = xy (.npy, text and .npz alike).
    np.save("xfirst.npy", Z.T)
    expect_refused(t, "xfirst.npy", "surface.layout = xy")
    expect_ok(t, "xfirst.npy", Z, extra_keys="layout = xy")
    np.savetxt("xfirst.txt", Z.T)
    expect_ok(t, "xfirst.txt", Z, extra_keys="layout = xy")
    np.save("yfirst.npy", Z)
    expect_refused(t, "yfirst.npy", "surface.layout = yx", extra_keys="layout = xy")
    p, _ = run(t, "yfirst.npy", extra_keys="layout = zx")
    check(p.returncode == 2 and "surface.layout" in p.stderr, "bad layout value")

if FAILURES:
    sys.exit(f"{len(FAILURES)} check(s) failed")
print("ok")
