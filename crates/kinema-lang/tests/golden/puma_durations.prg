// robot: puma560
// Durations given with IN and HOME t (the model's speed limits are estimates).
POS p = CART(500mm, 200mm, 300mm, 0deg, 180deg, 0deg)
PTP p IN 2s
LIN REL CART(0mm, -300mm, 0mm) IN 3s
PTP REL CART(0mm, 0mm, 100mm) IN 1s
HOME 2s
