"""Build step of the viscera client: generate viscera_proto from ../proto with lcm-gen.

The types are never committed (docs/protocol.md): like the C++ build, the package build
runs `lcm-gen --python` on every proto/*.lcm and ships the result beside viscera_client.
"""
import glob
import os
import shutil
import subprocess

from setuptools import setup
from setuptools.command.build_py import build_py

HERE = os.path.dirname(os.path.abspath(__file__))
PROTO_DIR = os.environ.get("VISCERA_PROTO_DIR", os.path.join(HERE, "..", "proto"))


class BuildWithProto(build_py):
    def run(self):
        super().run()
        sources = sorted(glob.glob(os.path.join(PROTO_DIR, "*.lcm")))
        if not sources:
            raise SystemExit(f"viscera-client: no .lcm files in {PROTO_DIR} (set VISCERA_PROTO_DIR)")
        lcm_gen = shutil.which("lcm-gen")
        if lcm_gen is None:
            raise SystemExit("viscera-client: lcm-gen not found (Debian: apt install liblcm-bin)")
        # one call for all types: the package __init__ must list every one of them
        subprocess.run([lcm_gen, "--python", "--ppath", self.build_lib, *sources], check=True)


setup(cmdclass={"build_py": BuildWithProto})
