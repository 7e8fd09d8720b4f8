#!/bin/sh
# Regenerates the mesh of the sphere-on-block example from sphere_on_block.geo
# (MSH 4.1 ASCII, tetrahedra): sphere_on_block.msh, n = 8 elements per mm (the
# designed contact radius) on the sphere near the contact, 1.25 × coarser on the block.
#
# Needs the gmsh command (`pip install gmsh`; in a virtual environment put its
# bin/ on PATH, as the wheel's gmsh script runs `python`). Gmsh 4.15.2 rewrites
# the committed file byte for byte. cfe itself does not need Gmsh: it reads the
# committed .msh file.
#
# Run from anywhere: sh examples/sphere_on_block/make_meshes.sh
set -e
cd "$(dirname "$0")"
gmsh sphere_on_block.geo -setnumber n 8 -3 -format msh41 -o sphere_on_block.msh
