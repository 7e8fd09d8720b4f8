#!/bin/sh
# Regenerates the meshes of the Hertz example from hertz.geo (MSH 4.1 ASCII):
#   hertz.msh                                  n = 10 elements per contact half-width
#   crates/cfe-tools/meshes/hertz_n{4,8,16,32}.msh  the verification's refinement levels
#
# Needs the gmsh command (`pip install gmsh`). cfe itself does not need Gmsh: it
# reads the committed .msh files.
#
# Run from anywhere: sh examples/hertz/make_meshes.sh
set -e
cd "$(dirname "$0")"
gmsh hertz.geo -setnumber n 10 -2 -format msh41 -o hertz.msh
mkdir -p ../../crates/cfe-tools/meshes
for n in 4 8 16 32; do
    gmsh hertz.geo -setnumber n $n -2 -format msh41 -o "../../crates/cfe-tools/meshes/hertz_n$n.msh"
done
