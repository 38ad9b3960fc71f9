// LBR iiwa 14 R820 at seed 004's fume hood (examples/scenes/fume-hood.toml):
// from upright, the tilted arm swings to one side of the hood, then to the
// other. Both straight joint motions pass through the lowered sash; AVOID
// lets them go around it when the program runs with the scene:
//
//   kinema run examples/programs/iiwa_hood_swing.prg --robot lbr-iiwa-14-r820 \
//       --scene examples/scenes/fume-hood.toml --out swing.csv
JVEL 50 deg/s
JACC 90 deg/s^2          // the model gives joint speeds (Cuadro I), not accelerations

POS left  = JOINT(-90deg, 60deg, 0, 0, 0, 0, 0)
POS right = JOINT(90deg, 60deg, 0, 0, 0, 0, 0)

PTP left AVOID
PTP right AVOID
