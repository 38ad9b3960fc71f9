// LBR iiwa 14 R820: a pen drawing a rounded rectangle on a table,
// with PTP, LIN, CIRC, blending, a relative move and a FOR loop.
PROFILE scurve
SPEED 80%
VEL 150 mm/s
ACC 800 mm/s^2
JACC 90 deg/s^2          // the model gives joint speeds (Cuadro I), not accelerations

POS above  = CART(550mm, -150mm, 400mm, 0deg, 180deg, 0deg)
POS corner = CART(550mm, -150mm, 250mm, 0deg, 180deg, 0deg)

PTP above
LIN corner
FOR i = 1 TO 2
  LIN REL CART(0mm, 250mm, 0mm) BLEND 20mm
  CIRC CART(600mm, 136.6mm, 250mm), CART(650mm, 100mm, 250mm, 0deg, 180deg, 0deg) BLEND 20mm
  LIN REL CART(0mm, -250mm, 0mm) BLEND 20mm
  CIRC CART(600mm, -186.6mm, 250mm), CART(550mm, -150mm, 250mm, 0deg, 180deg, 0deg)
  WAIT 0.5s
END
LIN above
HOME
