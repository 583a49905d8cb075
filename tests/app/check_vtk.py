"""Reads a run's growth.pvd and every .vtp it lists with VTK's own readers (python3-vtk9)
and checks the counts against the run's CSV files. Prints OK or the first problem."""
import csv
import os
import sys
import xml.etree.ElementTree as ET

import vtk


def fail(msg):
    print("FAIL " + msg)
    sys.exit(1)


def read(path):
    r = vtk.vtkXMLPolyDataReader()
    r.SetFileName(path)
    r.Update()
    if r.GetErrorCode() != 0:
        fail(f"{path}: VTK reader error {r.GetErrorCode()}")
    return r.GetOutput()


d = sys.argv[1]
neurons = list(csv.DictReader(open(os.path.join(d, "neurons.csv"))))
sources = list(csv.DictReader(open(os.path.join(d, "sources.csv")))) if os.path.exists(os.path.join(d, "sources.csv")) else []
particles = list(csv.DictReader(open(os.path.join(d, "particles.csv")))) if os.path.exists(os.path.join(d, "particles.csv")) else []
somas = read(os.path.join(d, "vtk", "somas.vtp"))
if somas.GetNumberOfPoints() != len(neurons) or somas.GetNumberOfVerts() != len(neurons):
    fail(f"somas: {somas.GetNumberOfPoints()} points for {len(neurons)} neurons")
status = somas.GetPointData().GetArray("status")
names = ["growing", "connected", "exited", "max_steps"]
for i in (0, len(neurons) // 2, len(neurons) - 1):
    if names[int(status.GetValue(i))] != neurons[i]["status"]:
        fail(f"somas: status of neuron {i}")
    p = somas.GetPoint(i)
    if abs(p[0] - float(neurons[i]["soma_x"])) > 1e-12:
        fail(f"somas: position of neuron {i}")
src = read(os.path.join(d, "vtk", "sources.vtp"))
if src.GetNumberOfPoints() != len(sources):
    fail(f"sources: {src.GetNumberOfPoints()} points for {len(sources)} sources")
# Particles per recorded step, and the recorded steps in order: a frame at step t holds the
# particles of the latest recorded step <= t.
per_step = {}
for p in particles:
    per_step[int(p["step"])] = per_step.get(int(p["step"]), 0) + 1
recorded = sorted(per_step)
steps = []
for ds in ET.parse(os.path.join(d, "growth.pvd")).getroot().iter("DataSet"):
    t = int(ds.get("timestep"))
    data = read(os.path.join(d, ds.get("file")))
    if ds.get("part") == "2":
        steps.append(t)
        grown = [n for n in neurons]
        if data.GetNumberOfLines() != len(grown):
            fail(f"axons at step {t}: {data.GetNumberOfLines()} lines for {len(grown)} axons")
        expect = sum(min(t, int(n["steps"])) + 1 for n in neurons)
        if data.GetNumberOfPoints() != expect:
            fail(f"axons at step {t}: {data.GetNumberOfPoints()} points, expected {expect}")
    if ds.get("part") == "3":
        latest = [k for k in recorded if k <= t]
        want = per_step[latest[-1]] if latest else 0
        if data.GetNumberOfPoints() != want:
            fail(f"particles at step {t}: {data.GetNumberOfPoints()} points, expected {want}")
if steps[0] != 0 or len(steps) < 2:
    fail(f"time series steps {steps}")
print(f"OK {len(neurons)} somas, {len(sources)} sources, {len(steps)} frames")
