"""Writes python_tour.ipynb from python_tour.py (cells split at `# %%`, Markdown cells at
`# %% [markdown]`), so the notebook and the script that the tests run are the same code.

    python examples/sync_notebook.py          # rewrite the notebook
    python examples/sync_notebook.py --check  # exit 1 if the notebook is out of date
"""

import json
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
SCRIPT, NOTEBOOK = HERE / "python_tour.py", HERE / "python_tour.ipynb"


def cells(text: str) -> list[dict]:
    out = []
    for chunk in text.split("# %%")[1:]:
        head, _, body = chunk.partition("\n")
        lines = body.strip("\n").splitlines()
        if head.strip() == "[markdown]":
            src = [line[2:] if line.startswith("# ") else line.lstrip("#") for line in lines]
            out.append({"cell_type": "markdown", "metadata": {}, "source": src})
        else:
            out.append({"cell_type": "code", "execution_count": None, "metadata": {},
                        "outputs": [], "source": lines})
    for c in out:  # notebook JSON keeps each line's newline but the last
        c["source"] = [line + "\n" for line in c["source"][:-1]] + c["source"][-1:]
    return out


def notebook() -> str:
    nb = {
        "cells": cells(SCRIPT.read_text()),
        "metadata": {"kernelspec": {"display_name": "Python 3", "language": "python",
                                    "name": "python3"},
                     "language_info": {"name": "python"}},
        "nbformat": 4, "nbformat_minor": 4,
    }
    return json.dumps(nb, indent=1, ensure_ascii=False) + "\n"


if __name__ == "__main__":
    text = notebook()
    if "--check" in sys.argv:
        if not NOTEBOOK.is_file() or NOTEBOOK.read_text() != text:
            sys.exit(f"{NOTEBOOK.name} is not {SCRIPT.name}: run python {Path(__file__).name}")
    else:
        NOTEBOOK.write_text(text)
