"""Shared by the tests that load axonguide's SWC in NEURON (test_arbour_clients.py,
test_synapse_clients.py): NEURON with Import3d, and one cell loaded alone."""


def neuron_with_import3d():
    from neuron import h  # python3-neuron, installed by scripts/install-deps.sh
    h.load_file("stdlib.hoc")
    h.load_file("import3d.hoc")
    return h


def load_cell(h, path):
    """Deletes every section, loads the SWC at path with Import3d; {name: section}."""
    for sec in list(h.allsec()):
        h.delete_section(sec=sec)
    reader = h.Import3d_SWC_read()
    reader.quiet = 1
    reader.input(str(path))
    h.Import3d_GUI(reader, 0).instantiate(None)
    return {sec.name(): sec for sec in h.allsec()}
