"""The guide's picture of a dem2d run in OVITO (figures/ovito_hopper.png): the LAMMPS dump that
`dem2d export` writes, opened with OVITO's Python module (`pip install ovito`), the grains
coloured by their speed (OVITO's own Velocity Magnitude, Viridis), seen from above and rendered
offscreen by OVITO's Tachyon renderer.

    python figures/scripts/ovito_render.py RUN_DIR FRAME OUT.png

RUN_DIR holds `dump.lammpstrj` (`dem2d run --dump`, or `dem2d export RUN_DIR --format
lammps-dump`). The box drawn is the dump's (the bodies' and walls' extent); the walls themselves
are not in a LAMMPS dump, which holds particles only.
"""

import sys

from ovito.io import import_file
from ovito.modifiers import ColorCodingModifier
from ovito.vis import TachyonRenderer, Viewport

run, frame, out = sys.argv[1], int(sys.argv[2]), sys.argv[3]
pipeline = import_file(f"{run}/dump.lammpstrj")
pipeline.modifiers.append(
    ColorCodingModifier(
        property="Velocity Magnitude",
        gradient=ColorCodingModifier.Viridis(),
        start_value=0.0,
        end_value=60.0,
    )
)
pipeline.add_to_scene()
vp = Viewport(type=Viewport.Type.Top)
vp.zoom_all(size=(1000, 700))
vp.render_image(
    size=(1000, 700), filename=out, frame=frame, background=(1, 1, 1), renderer=TachyonRenderer()
)
print(out)
