// Seed 004 §VIII-E, robot 1 (the cell's `holder`): holds the part with its
// tool pointing along +x, towards robot 2, then turns it by 90° about the
// tool axis. Positions are in the cell's world frame (the robot stands at
// its origin).
PROFILE scurve
JACC 90 deg/s^2           // Cuadro I gives joint speeds, not accelerations
VEL 200 mm/s
ACC 500 mm/s^2

POS hold = CART(550mm, 0mm, 600mm, 0deg, 90deg, 0deg)

PTP hold
// A turn about the tool axis, which is world x here: REL turns about the world axes.
LIN REL CART(0mm, 0mm, 0mm, 90deg, 0deg, 0deg)
