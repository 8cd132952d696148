"""Run by pvpython under Xvfb (tests/python/paraview_xmf_test.py): opens result.xmf with
ParaView's readers as a user would and prints what it sees as one JSON object.

usage: pvpython paraview_read_xmf.py RESULT.xmf SCREENSHOT.png
For each Xdmf3 reader (Xdmf3ReaderS, the one OpenDataFile picks, and Xdmf3ReaderT):
the time values, and per time step the bounds, the cell count and the sum of the cell
pressures. Then the first step shown in a render view as ParaView's GUI shows a new source
(default camera, coloured by pressure), saved as a screenshot whose pixels are counted.
"""
import json
import sys

from paraview import servermanager
from paraview.simple import (ColorBy, GetActiveViewOrCreate, OpenDataFile, Render,
                             SaveScreenshot, Show, Xdmf3ReaderT)
from vtkmodules.vtkIOImage import vtkPNGReader
from vtkmodules.util.numpy_support import vtk_to_numpy

XMF, PNG = sys.argv[1], sys.argv[2]


def first_block(data):
    return data.GetBlock(0) if data.IsA("vtkMultiBlockDataSet") else data


def describe(reader):
    times = list(reader.TimestepValues)
    steps = []
    for t in times:
        reader.UpdatePipeline(time=t)
        block = first_block(servermanager.Fetch(reader))
        p = block.GetCellData().GetArray("pressure")
        steps.append({"time": t, "bounds": list(block.GetBounds()),
                      "cells": block.GetNumberOfCells(),
                      "pressure_sum": float(vtk_to_numpy(p).sum()) if p else None})
    return {"times": times, "steps": steps}


out = {}
default = OpenDataFile(XMF)
out["default_reader"] = default.GetXMLName()
out[out["default_reader"]] = describe(default)
out["Xdmf3ReaderT"] = describe(Xdmf3ReaderT(FileName=[XMF]))

view = GetActiveViewOrCreate("RenderView")
view.ViewSize = [400, 300]
view.ViewTime = default.TimestepValues[0]
display = Show(default, view)
ColorBy(display, ("CELLS", "pressure"))
display.RescaleTransferFunctionToDataRange(True, False)
Render(view)
SaveScreenshot(PNG, view, ImageResolution=[400, 300], TransparentBackground=0)
png = vtkPNGReader()
png.SetFileName(PNG)
png.Update()
pixels = vtk_to_numpy(png.GetOutput().GetPointData().GetScalars())[:, :3]
background = pixels[0]  # a corner: the view's background
colours = {tuple(int(c) for c in px) for px in pixels[::7]}
out["image"] = {"pixels": int(len(pixels)),
                "not_background": int((pixels != background).any(axis=1).sum()),
                "colours": len(colours)}
print("RESULT " + json.dumps(out))
