// robot: scara5
// Every instruction of seed 003 Fig. 8, as printed.
HOME 2;
PAUSE 0.5;
MOVEZ -40, 1;
MOVETITA +30, 0.5;
MOVEXY 120, -150, 2;
LOOP 2
  MOVEXY -20, 0, 0.5;
  // a comment inside the loop
  MOVEZ +10, 0.25;
END
HOME 2;
