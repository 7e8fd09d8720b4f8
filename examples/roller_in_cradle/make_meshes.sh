#!/bin/sh
# Regenerates the meshes of the "roller in cradle" example from their Gmsh
# geometry files: roller.geo -> roller.msh, cradle.geo -> cradle.msh (MSH 4.1 ASCII).
#
# Needs the gmsh command (`pip install gmsh`). cfe itself does not need Gmsh: it
# reads the committed .msh files.
#
# Run from anywhere: sh examples/roller_in_cradle/make_meshes.sh
set -e
cd "$(dirname "$0")"
for part in roller cradle; do
    gmsh "$part.geo" -2 -format msh41 -o "$part.msh"
done
