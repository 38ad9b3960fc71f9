// Seed 004 §VIII-E, robot 2 (the cell's `drawer`): stands 1.2 m from
// robot 1, turned by 180°, and draws a circle of 5 cm radius about the
// part's axis (world x), 12 cm in front of the part, its tool pointing back
// at it (along −x). Positions are in the cell's world frame.
PROFILE trapezoid
JACC 90 deg/s^2
VEL 200 mm/s
ACC 500 mm/s^2

POS start = CART(670mm, 0mm, 550mm, 0deg, -90deg, 0deg)
POS top   = CART(670mm, 0mm, 650mm, 0deg, -90deg, 0deg)

PTP start
CIRC CART(670mm, 50mm, 600mm), top BLEND 10mm
CIRC CART(670mm, -50mm, 600mm), start
