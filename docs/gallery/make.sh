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
# Fig. 5–6: desired square and measured runs. No measurements ship with the
# project yet: the runs are the commanded square plus Gaussian noise, three
# seeded repetitions, σ = 1.36 mm per axis so that the mean distance to the
# path (σ·√(π/2) for the two axes across it) is seed 000's 1.7 mm.
$k run examples/programs/scorbot_square.prg --robot scorbot-er-v-plus --dt 0.05 --out $tmp/square.csv
python3 - "$tmp" <<'PY'
import csv, random, sys
tmp = sys.argv[1]
rows = list(csv.DictReader(open(f"{tmp}/square.csv")))
pts = [(float(r["x"]), float(r["y"]), float(r["z"])) for r in rows]
# The square itself: the samples at the program's pen height, 150 mm, in order.
square = [p for p in pts if abs(p[2] - 0.150) < 1e-6]
with open(f"{tmp}/desired.csv", "w") as f:
    f.write("x,y,z\n")
    for p in square:
        f.write("%.6f,%.6f,%.6f\n" % p)
for run in range(3):
    rng = random.Random(run)
    with open(f"{tmp}/measured{run}.csv", "w") as f:
        f.write("x,y,z\n")
        for p in square[::4]:
            f.write("%.6f,%.6f,%.6f\n" % tuple(v + rng.gauss(0, 0.00136) for v in p))
PY
$k plot tracking --desired $tmp/desired.csv --measured $tmp/measured0.csv $tmp/measured1.csv $tmp/measured2.csv \
  --out $out/seed000-fig6-tracking.png

# Seed 001 (ROMMEL): §4.2's joint-1 trajectory θ1 = 3·sin(4πt²/2), Fig. 8.
$k traj expr --robot rommel --joint 1 "3*sin(4*pi*t^2/2)" --duration 2 --dt 0.002 --out $tmp/rommel.csv
$k plot traj --robot rommel --csv $tmp/rommel.csv --out $out/seed001-fig8-joints.png

# Seed 003 (SCARA on a rail): Fig. 3, the workspace with the rail.
$k plot workspace --robot scara5 --out $out/seed003-fig3-workspace.png
$k plot traj --robot scara5 --program examples/programs/scara_pick_place.prg --out $out/seed003-joints.png

# Seed 004 (KUKA LBR iiwa 14 R820)
$k plot workspace --robot $iiwa --out $out/seed004-fig4-workspace.png
$k plot robot --robot $iiwa --q $q_iiwa --3d --out $out/seed004-fig5-frames.png
$k plot ik-error --robot $iiwa --cases 1000 --out $out/seed004-fig6-ik-error.png
$k plot selfmotion --robot $iiwa --q $q_iiwa --out $out/seed004-fig7-selfmotion.png
$k plot ellipsoid --robot $iiwa --q $q_iiwa --out $out/seed004-fig9-ellipsoids.png
$k plot traj --robot $iiwa --program examples/programs/iiwa_draw.prg --out $out/seed004-fig20-joints.png
$k plot traj --robot $iiwa --program examples/programs/iiwa_draw.prg --kind cartesian --out $out/seed004-cartesian.png
$k plot traj --robot $iiwa --program examples/programs/iiwa_draw.prg --kind path --out $out/seed004-tool-path.png
$k plot traj --robot $iiwa --program examples/programs/iiwa_draw.prg --kind manipulability \
  --out $out/seed004-fig30-manipulability.png
