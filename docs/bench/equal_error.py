#!/usr/bin/env python3
# lensray bench JSON -> for each point of a path (default: hybrid), the time the other path
# (default: software) needs for the same RMSE (log-log interpolation between its sweep points),
# over the path's own. Usage: equal_error.py FILE.json [OTHER_PATH [PATH]]
import json, math, sys
# Time at equal error: for each hybrid point, the software time to reach its RMSE (log-log
# interpolation between software's sweep points), over the hybrid's time.
d = json.load(open(sys.argv[1]))
pts = {}
for p in d["points"]:
    for r in p["results"]:
        pts.setdefault(r["path"], []).append((p["spp"], r["trace_seconds"]["median"], r["rmse"]))
base = sys.argv[2] if len(sys.argv) > 2 else "software"
sw = sorted(pts[base], key=lambda x: x[2])
def t_at(e):
    # sw sorted by error ascending
    for (s1,t1,e1),(s0,t0,e0) in zip(sw, sw[1:]):
        if e1 <= e <= e0:
            f = (math.log(e)-math.log(e0))/(math.log(e1)-math.log(e0))
            return math.exp(math.log(t0)+f*(math.log(t1)-math.log(t0)))
    # extrapolate with error ~ t^-1/2 from nearest
    s,t,e1 = min(sw, key=lambda x: abs(math.log(x[2]/e)))
    return t*(e1/e)**2
path = sys.argv[3] if len(sys.argv) > 3 else "hybrid"
for s,t,e in sorted(pts[path]):
    ts = t_at(e)
    print(f"spp {s:3d}: {path} {t*1e3:8.0f} ms RMSE {e:.3e}; {base} reaches that RMSE in {ts*1e3:8.0f} ms: {ts/t:.2f}x")
