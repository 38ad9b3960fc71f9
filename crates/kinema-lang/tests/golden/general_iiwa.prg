// robot: lbr-iiwa-14-r820
// Every statement of the general language on the iiwa.
PROFILE scurve
SPEED 80%
ACC 90%
VEL 200 mm/s
VEL 60 deg/s
ACC 1 m/s^2
ACC 120 deg/s^2
JVEL 60 deg/s
JACC 90 deg/s^2
TOOL CART(0mm, 0mm, 50mm, 0deg, 0deg, 0deg)
BASE CART(0mm, 0mm, 0mm, 0deg, 0deg, 0deg)
POS above = CART(550mm, -150mm, 400mm, 0deg, 180deg, 0deg)
POS bent = JOINT(0deg, 30deg, 0deg, -60deg, 0deg, 60deg, 0deg)
PTP bent
// joint targets in the listing stay independent of the q3 rule's path
PTP REL JOINT(5deg, 0, 0, 0, 0, 0, 0) IN 1s
PTP above
LIN REL CART(0mm, 0mm, -100mm)
FOR i = 1 TO 2
  LIN REL CART(0mm, 100mm * i, 0mm) BLEND 20mm
  CIRC CART(600mm, 100mm * i - 100mm, 300mm), CART(650mm, -150mm + 100mm * i, 300mm, 0deg, 180deg, 0deg) BLEND 0.1s
  LIN CART(550mm, -150mm, 300mm, 0deg, 180deg, 0deg)
END
LIN REL CART(0mm, 0mm, 50mm) IN 2s
WAIT 250ms
PAUSE 0.25
HOME 4s
