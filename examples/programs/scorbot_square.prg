// Scorbot-ER V Plus: the square of seed 000 Fig. 6, traced with the pen
// vertical (the 5-DOF arm cannot choose its yaw, but with a vertical
// approach the roll joint absorbs it, so every pose of the path is exact).
// The model gives no joint speed limits: PTP and HOME take durations.
VEL 20 mm/s                       // slow, as for the camera measurements of §IV
ACC 100 mm/s^2
POS a = CART(350mm, -50mm, 150mm, 0deg, 180deg, 0deg)
POS b = CART(450mm, -50mm, 150mm, 0deg, 180deg, 0deg)
POS c = CART(450mm,  50mm, 150mm, 0deg, 180deg, 0deg)
POS d = CART(350mm,  50mm, 150mm, 0deg, 180deg, 0deg)
PTP a IN 4s
LOOP 2                            // seed 000 repeated its paths to measure the spread
  LIN b
  LIN c
  LIN d
  LIN a
END
HOME 4s
