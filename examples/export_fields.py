"""Export of series and fields: xarray, netCDF and CSV
=====================================================

Results leave mdrvisc in the formats the ecosystem reads. ``Result.to_xarray()`` gives an
``xarray.Dataset`` (``pip install 'mdrvisc[xarray]'``): the series over the output times
``t``, the fields over their times ``field_t`` and the element centres ``y``, ``x`` (or the
radii ``r`` of an MDR profile), each with its unit, and the run's numbers as attributes. It
writes netCDF with ``to_netcdf``, which tamaas' and ContactMechanics' users, ParaView and
most plotting tools read. ``Result.to_csv(path)`` writes the series as a CSV file, and
``Result.save(path)`` the whole result as ``.npz`` (``mv.Result.load`` reads it back).

Here a rough surface creeps into a standard solid; its contact pressure and gap at two
times are exported and read back. The files go to a temporary folder.

Run: python examples/export_fields.py [OUT.png]   (default OUT: export_fields.png)
"""

import argparse
import tempfile
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402

import mdrvisc as mv  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description="Export of series and fields")
    parser.add_argument("out", nargs="?", default="export_fields.png")
    args = parser.parse_args()

    n, dx = 128, 1e-6
    heights = mv.surfaces.self_affine((n, n), dx, hurst=0.8, rms_slope=0.1, rolloff=64e-6,
                                      short_cutoff=16e-6, seed=3)
    scene = mv.Scene(indenter=mv.HeightMap(heights, dx, periodic=True),
                     medium=mv.StandardSolid(G_inf=1e6, G1=4e6, tau1=1.0),
                     force=0.1 * 4e6 * 0.1 * (n * dx) ** 2, duration=20.0,
                     times=np.geomspace(0.05, 20.0, 12), dt=0.25, field_times=[0.05, 20.0],
                     outputs=("depth", "pressure", "gap"))
    result = mv.solve(scene)

    data = result.to_xarray()
    print(data)

    folder = Path(tempfile.mkdtemp())
    netcdf = folder / "creep.nc"
    data.to_netcdf(netcdf)
    series = result.to_csv(folder / "creep.csv", units=True)
    saved = result.save(folder / "creep.npz")
    for path in (netcdf, series, saved):
        print(f"{path.name}: {path.stat().st_size} bytes")
    print("".join(series.read_text().splitlines(keepends=True)[:4]))

    with xr.open_dataset(netcdf) as back:
        same = all(np.array_equal(back[k].values, data[k].values) for k in data.variables)
        print("netCDF read back equal:", same, "| units of pressure:", back.pressure.attrs["units"])

    fig, axes = plt.subplots(1, 2, figsize=(10.0, 4.2), sharey=True)
    for ax, t in zip(axes, data.field_t.values):
        (data.pressure.sel(field_t=t) / 1e6).plot(ax=ax, cmap="magma",
                                                  cbar_kwargs={"label": "pressure (MPa)"})
        ax.set_title(f"t = {t:g} s, contact fraction "
                     f"{float(data.contact_fraction.sel(t=t)):.3f}")
        ax.set_aspect("equal")
    fig.tight_layout()
    fig.savefig(args.out, dpi=100)
    plt.close(fig)
    print(f"wrote {Path(args.out).name}")


if __name__ == "__main__":
    main()
