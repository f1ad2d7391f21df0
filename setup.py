"""The build copies the package's data files (planner.core.resources.DATA) into the wheel, under planner/_data/."""

import runpy
import shutil
from pathlib import Path

from setuptools import setup
from setuptools.command.build_py import build_py

# read from the module itself (it imports nothing of the package), so the list has one home
DATA = runpy.run_path(str(Path(__file__).resolve().parent / "planner" / "core" / "resources.py"))["DATA"]


class BuildWithData(build_py):
    def run(self) -> None:
        super().run()
        root = Path(__file__).resolve().parent
        target = Path(self.build_lib) / "planner" / "_data"
        target.mkdir(parents=True, exist_ok=True)
        for name, source in DATA.items():
            if (root / source).is_dir():
                shutil.copytree(root / source, target / name, dirs_exist_ok=True)
            else:
                shutil.copy2(root / source, target / name)


setup(cmdclass={"build_py": BuildWithData})
