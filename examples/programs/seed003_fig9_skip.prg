// Seed 003 Fig. 9: a path through points, one of them out of reach.
HOME 1
MOVEXY 100, 50, 1
MOVEXY 2000, 0, 1
MOVEXY -100, 100, 1
