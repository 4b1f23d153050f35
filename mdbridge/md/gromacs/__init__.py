"""GROMACS side of dnarod: periodic, ligated all-atom DNA from rod initial conditions.

One concept per module:
- `gmx`        find the user's gmx, run it, turn its failures into ExternalToolError
- `gro`        read/write .gro (coordinates, velocities, box)
- `defaults`   every default of build-md and run-md, in one place
- `mdp`        the md.mdp / em.mdp settings (paper Sec 6.2 defaults)
- `topology`   pdb2gmx with ring closure across the periodic boundary, .itp parsing
- `junction`   verify by code that each ring junction has exactly an interior step's terms
- `charges`    electrostatics variants (neutralised phosphates)
- `box`        box sizing from the rod's own predicted transverse excursion
- `velocities` Maxwell-Boltzmann thermal part + the rod cross-section's rigid-body motion
- `rod`        the rod side of a build: the sizing run, the state at t = 0 (RodInitial)
- `inputs`     assemble DIR/conf.gro, topol.top, md.mdp, em.mdp, build.json
- `run`        grompp + mdrun with progress, outputs that never look finished when they are not
- `checks`     DIR/checks.json after a run (junctions, drift, pairing, frames, image distance)
- `tension`    axial tension -P_aa x A from an energy file, its error, a box stretched along the axis
"""
