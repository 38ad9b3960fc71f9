// robot: puma560
// A robot whose model has no speed limits: durations given with IN and HOME t.
POS p = CART(500mm, 200mm, 300mm, 0deg, 180deg, 0deg)
PTP p IN 2s
LIN REL CART(0mm, -300mm, 0mm) IN 3s
PTP REL CART(0mm, 0mm, 100mm) IN 1s
HOME 2s
