"""A figure saved under a temporary name and renamed: whole under its name, or not there."""
import os
from pathlib import Path


def savefig_whole(fig, path, **kwargs):
    path = Path(path)
    tmp = path.with_name(".{}.tmp-{}".format(path.name, os.getpid()))
    try:
        fig.savefig(tmp, format=path.suffix.lstrip(".") or "png", **kwargs)
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()
