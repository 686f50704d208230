"""Runs a notebook's code cells in order, in one namespace, from the notebook's folder: the
tour (examples/python/tour.ipynb) is tested as written without Jupyter. Its figures are
written to a temporary folder."""
import json
import os
import pathlib
import sys
import tempfile

notebook = pathlib.Path(sys.argv[1]).resolve()
cells = json.loads(notebook.read_text())["cells"]
namespace = {"__name__": "__main__"}
os.chdir(notebook.parent)
with tempfile.TemporaryDirectory() as figures:
    for number, cell in enumerate(cells):
        if cell["cell_type"] != "code":
            continue
        source = "".join(cell["source"])
        # Figures go to the temporary folder, not beside the notebook in the source tree.
        source = source.replace('fig.savefig("', f'fig.savefig("{figures}/')
        exec(compile(source, f"{notebook.name} cell {number}", "exec"), namespace)
    written = sorted(os.listdir(figures))
    assert written == ["tour_error.png", "tour_relit.png"], written
print(f"{notebook.name}: {sum(c['cell_type'] == 'code' for c in cells)} cells ran")
