// Seed 003 (Fig. 8): the SCARA's own instruction set, a pick-and-place loop.
// Lengths in mm, angles in degrees, times in seconds, every move relative.
HOME 3;
LOOP 3
  MOVEXY 150, -200, 2;   // over the pick point
  MOVEZ -80, 1;          // down to the part
  PAUSE 0.5;             // close the gripper
  MOVEZ +80, 1;          // up
  MOVETITA 90, 1;        // turn the part a quarter
  MOVEXY -150, 200, 2;   // over the place point
  MOVEZ -80, 1;
  PAUSE 0.5;             // open the gripper
  MOVEZ +80, 1;
  MOVETITA -90, 1;
END
HOME 3;
