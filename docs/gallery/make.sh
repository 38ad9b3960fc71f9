#!/usr/bin/env bash
# Regenerates docs/gallery/*.png: one picture per seed figure that kinema
# reproduces (see docs/gallery/README.md). Run from anywhere:
#   bash docs/gallery/make.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
cargo build -q --release -p kinema-cli --locked
k=target/release/kinema
out=docs/gallery
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

iiwa=lbr-iiwa-14-r820
q_iiwa=0.3,0.6,0.4,-1.2,0.3,0.9,0.1

# Seed 000 (Scorbot-ER V Plus)
$k plot robot --robot scorbot-er-v-plus --q home --out $out/seed000-fig2-robot.png
$k plot workspace --robot scorbot-er-v-plus --out $out/seed000-fig2-workspace.png
# Fig. 6: the square in the xz plane (y = 0), as the seed has it, followed on the
# controller simulator (`kinema scorbot square`): planned with the factory
# constants (Tabla II/III) and with the arm's true ones (the seed's calibrated
# columns), two runs each. The "measured" paths are SIMULATED: the simulator's
# tool path every 10 ms of motion plus Gaussian noise of 1 mm per axis (the
# seed's camera precision), seed 0. docs/seeds.md compares them with 0.17/0.47 cm.
$k scorbot square --plane xz --runs 2 --noise-mm 1 --seed 0 --out-dir $tmp/fig6
$k plot tracking --desired $tmp/fig6/desired.csv --measured $tmp/fig6/factory-1.csv $tmp/fig6/factory-2.csv \
  --out $out/seed000-fig6-factory.png
$k plot tracking --desired $tmp/fig6/desired.csv --measured $tmp/fig6/calibrated-1.csv $tmp/fig6/calibrated-2.csv \
  --out $out/seed000-fig6-corrected.png

# Seed 001 (ROMMEL): §4.2's joint-1 trajectory θ1 = 3·sin(4πt²/2), Fig. 8.
$k traj expr --robot rommel --joint 1 "3*sin(4*pi*t^2/2)" --duration 2 --dt 0.002 --out $tmp/rommel.csv
$k plot traj --robot rommel --csv $tmp/rommel.csv --out $out/seed001-fig8-joints.png

# Seed 003 (SCARA on a rail): Fig. 3, the workspace with the rail.
$k plot workspace --robot scara5 --out $out/seed003-fig3-workspace.png
$k plot traj --robot scara5 --program examples/programs/scara_pick_place.prg --out $out/seed003-joints.png

# Seed 004 (KUKA LBR iiwa 14 R820), at the seed's own configurations.
$k plot workspace --robot $iiwa --out $out/seed004-fig4-workspace.png
# Fig. 5: every joint at π/6.
$k plot robot --robot $iiwa --q 30,30,30,30,30,30,30 --deg --3d --out $out/seed004-fig5-frames.png
$k plot ik-error --robot $iiwa --cases 1000 --out $out/seed004-fig6-ik-error.png
# Fig. 7: the seed gives no configuration; any one within the limits.
$k plot selfmotion --robot $iiwa --q $q_iiwa --out $out/seed004-fig7-selfmotion.png
# Fig. 9–10 at q = (0, π/6, 0, −π/3, 0, −π/3, 0) (pose `fig9`); Fig. 11–13 at the
# singular configurations of Cuadro III.
$k plot ellipsoid --robot $iiwa --q fig9 --out $out/seed004-fig9-ellipsoids.png
$k plot ellipsoid --robot $iiwa --q sing-q4 --out $out/seed004-fig11-ellipsoids.png
$k plot ellipsoid --robot $iiwa --q sing-q2-q3 --out $out/seed004-fig12-ellipsoids.png
$k plot ellipsoid --robot $iiwa --q sing-coupled --out $out/seed004-fig13-ellipsoids.png
# Fig. 15, 20, 21: the PTP example of §VIII-B, from q = 0 to the seed's q_obj, with
# the seed's trapezoid; Cuadro I gives no acceleration limit, 2 rad/s² is assumed.
q_obj=-0.1090,1.2417,0.4463,1.9156,-0.9695,-1.8728,0.4876
$k traj ptp --robot $iiwa --from home --to=$q_obj --profile trapezoid --amax 2 --out $tmp/ptp.csv
$k plot traj --robot $iiwa --csv $tmp/ptp.csv --out $out/seed004-fig20-joints.png
$k plot traj --robot $iiwa --csv $tmp/ptp.csv --kind cartesian --out $out/seed004-fig21-cartesian.png
$k plot traj --robot $iiwa --csv $tmp/ptp.csv --kind path --out $out/seed004-fig15-path.png
# No seed configuration: a program of kinema's language on the iiwa (LIN, CIRC, PTP).
$k plot traj --robot $iiwa --program examples/programs/iiwa_draw.prg --kind cartesian --out $out/seed004-cartesian.png
$k plot traj --robot $iiwa --program examples/programs/iiwa_draw.prg --kind path --out $out/seed004-tool-path.png
$k plot traj --robot $iiwa --program examples/programs/iiwa_draw.prg --kind manipulability \
  --out $out/seed004-fig30-manipulability.png
