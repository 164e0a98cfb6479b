"""PyFMRheo side of bench_force_map.py's comparison: PyFMRheo's power-law Ting fit
(``pyfmrheo.routines.TingFit.doTingFit``) of curves of a JPK force map, run in PyFMRheo's own
environment, with the parameters of PyFMRheo's ViscoelasticFitExample notebook (paraboloid
R = 5 µm, Poisson ratio 0.5, contact point by the RoV method refined by a Hertz fit,
baseline offset from the lowest 30 % of the height range, the data from 1 µm before contact,
downsampled to 300 points, t0 = 1 s, viscous drag 2.5e-6 N s/m, the "analytical" model).

This file imports neither mdrvisc nor the benchmark helpers (``pip install pyfmrheo
pyfmreader`` in a venv of its own). The driver calls, with PYTHON that venv's interpreter,

    PYTHON pyfmrheo_map_worker.py --map FILE.jpk-force-map --curves 0 1 2

and reads one JSON document from the last line of stdout: per curve PyFMRheo's fitted E0,
betaE, tc, F0 (and the Hertz fit's E0 and contact-point shift), the speeds v0t and v0r it
assumed, the spring constant, and the window it fitted: times (s, from the fitted contact
time's first guess), indentation (m) and force (N) at the downsampled samples, idx_tm, and
its model at the solution.
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--map", required=True)
    ap.add_argument("--curves", type=int, nargs="+", default=[0])
    args = ap.parse_args()

    from importlib.metadata import version

    from pyfmreader import loadfile
    from pyfmrheo.routines.TingFit import doTingFit

    file = loadfile(args.map)
    meta = file.filemetadata
    k = meta["spring_const_Nbym"]
    params = {
        "height_channel": meta["height_channel_key"], "def_sens": meta["defl_sens_nmbyV"] / 1e9, "k": k,
        "contact_model": "paraboloid", "tip_param": 5e-6, "curve_seg": "extend", "correct_tilt": False,
        "tilt_min_offset": 1e-8, "tilt_max_offset": 1e-6, "poisson": 0.5, "poc_method": "RoV",
        "poc_win": 4e-7, "max_ind": 0.0, "min_ind": 0.0, "max_force": 0.0, "min_force": 0.0,
        "fit_range_type": "full", "vdragcorr": False, "polyordr": 2, "rampspeed": 0.0,
        "compute_v_flag": False, "t0": 1, "d0": 0.0, "slope": 0.0, "auto_init_E0": True, "E0": 1000,
        "tc": 0.0, "auto_init_betaE": True, "fluid_exp": 0.2, "f0": 0.0, "vdrag": 2.5e-6,
        "model_type": "analytical", "smoothing_win": 5, "contact_offset": 1e-6, "fit_line": False,
        "downsample_flag": True, "pts_downsample": 300, "offset_type": "percentage", "max_offset": 0.3,
        "min_offset": 0,
    }
    out = {"pyfmrheo": version("pyfmrheo"), "spring_constant": k, "curves": []}
    for index in args.curves:
        curve = file.getcurve(index)
        curve.preprocess_force_curve(params["def_sens"], params["height_channel"])
        if meta["file_type"] in ("jpk-force", "jpk-force-map", "jpk-qi-data"):
            curve.shift_height()
        start = time.perf_counter()
        ting, hertz = doTingFit(curve, params)
        wall = time.perf_counter() - start
        ext, ret = curve.get_segments()[0][1], curve.get_segments()[1][1]
        # the window doTingFit fitted, rebuilt as it builds it
        idx_tc = int(np.abs(ext.indentation).argmin())
        t_end = ext.time[-1]
        indentation = np.r_[ext.indentation, ret.indentation]
        times = np.r_[ext.time, ret.time + t_end]
        force = np.r_[ext.force, ret.force]
        mask = indentation > -params["contact_offset"]
        tc = times[idx_tc]
        ind_fit, force_fit, time_fit = indentation[mask], force[mask], times[mask]
        force_fit = force_fit - force_fit[0]
        time_fit = time_fit - time_fit[0] - (tc - time_fit[0])
        down = list(range(0, len(time_fit), len(time_fit) // params["pts_downsample"]))
        model = ting.eval(time_fit[down], force_fit[down], ind_fit[down], t0=1, idx_tm=ting.idx_tm,
                          smooth_w=ting.smooth_w, v0t=ting.v0t, v0r=ting.v0r)
        out["curves"].append({
            "index": index, "E0": float(ting.E0), "betaE": float(ting.betaE), "tc": float(ting.tc),
            "F0": float(ting.F0), "hertz_E0": float(hertz.E0), "hertz_delta0": float(hertz.delta0),
            "v0t": float(ting.v0t), "v0r": float(ting.v0r), "idx_tm": int(ting.idx_tm), "wall": wall,
            "t": time_fit[down].tolist(), "indentation": ind_fit[down].tolist(),
            "force": force_fit[down].tolist(), "model": np.asarray(model, dtype=float).tolist(),
            "raw_height": np.r_[ext.zheight, ret.zheight].tolist(),
            "raw_deflection": np.r_[ext.vdeflection, ret.vdeflection].tolist(),
            "raw_time": times.tolist(), "raw_approach": int(len(ext.zheight)),
        })
    print(json.dumps(out))


if __name__ == "__main__":
    main()
