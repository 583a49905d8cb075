"""SWC files as rows, for the tests that read the command's morphologies (test_swc.py,
test_arbour_clients.py): (id, type, x, y, z, radius, parent) per sample, comments skipped,
seven columns each."""


def read_swc(path):
    rows = []
    for line in path.read_text().splitlines():
        if line.startswith("#") or not line.strip():
            continue
        c = line.split()
        assert len(c) == 7, line
        rows.append((int(c[0]), int(c[1]), float(c[2]), float(c[3]), float(c[4]), float(c[5]), int(c[6])))
    return rows
