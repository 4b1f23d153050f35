load MDDIR/conf.gro, md
load rod_atoms.gro, rod
load_traj rod_atoms.xtc, rod
load rod_coarse.pdb, beads
hide everything
show lines, md
color grey60, md
show sticks, rod
set stick_radius, 0.12
color marine, rod and elem C
show spheres, beads and name C
show sticks, beads
set sphere_scale, 0.6, beads
color orange, beads and name C
color red, beads and name D1
set state, 101
turn y, 0
orient md
turn x, -90
set ray_opaque_background, 1
bg_color white
png docs/figures/viewing_overlay.png, width=1000, height=600, dpi=100, ray=1
