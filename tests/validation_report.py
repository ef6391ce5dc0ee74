#!/usr/bin/env python3
"""Plots the validation numbers (tests/validate) and writes the report page.

    validation_report.py DATA_DIR OUT_DIR VERSION

DATA_DIR holds the CSV files of tools/validation_data and astm_g173.csv of
tests/physics/test_astm_g173.c; OUT_DIR receives README.md and the PNG plots.  Every comparison with
a published or independent value is also a check: the script exits non-zero when one fails, with the
same tolerances as the tests that own those values.
"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

DATA, OUT, VERSION = sys.argv[1], sys.argv[2], sys.argv[3]
failures = []

# OPAC's typical mixtures, boundary layer only, AOD(550) at each biome's default humidity (80 % for
# the maritime and polar biomes, 50 % otherwise), as computed in PHYSICS.md 5.3 from Hess, Koepke &
# Schult (1998); the same numbers tests/physics/test_aerosol.c checks the biomes against.
OPAC_BOUNDARY_LAYER = {"remote-continental": 0.032, "rural": 0.093, "urban": 0.465, "desert-dust": 0.263,
                       "maritime-clean": 0.078, "polar-arctic": 0.045, "polar-antarctic": 0.066}


def rows(name):
    with open(os.path.join(DATA, name)) as f:
        return list(csv.DictReader(f))


def number(x):
    return float(x) if x not in ("", "nan", "-nan") else math.nan


def save(fig, name):
    fig.tight_layout()
    fig.savefig(os.path.join(OUT, name), dpi=110)
    plt.close(fig)


def profiles():
    data = rows("profiles.csv")
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    worst_z = 0.0
    for ax, curve, label in ((axes[0], "almucantar", "azimuth from the sun (deg)"),
                             (axes[1], "vertical", "view zenith angle, sun side negative (deg)")):
        for lam in sorted({r["wavelength_nm"] for r in data}, key=float):
            sel = [r for r in data if r["curve"] == curve and r["wavelength_nm"] == lam]
            x = [number(r["angle_deg"]) for r in sel]
            line, = ax.semilogy(x, [number(r["fast"]) for r in sel], label="%s nm" % lam)
            ref = [r for r in sel if not math.isnan(number(r["reference"]))]
            ax.errorbar([number(r["angle_deg"]) for r in ref], [number(r["reference"]) for r in ref],
                        yerr=[2 * number(r["reference_se"]) for r in ref], fmt="o", ms=3, color=line.get_color())
            for r in ref:
                # the map is bilinear between pixel centres: its own interpolation error counts too
                z = abs(number(r["fast"]) - number(r["reference"])) / math.hypot(
                    number(r["reference_se"]), 0.01 * number(r["reference"]))
                worst_z = max(worst_z, z)
        ax.set_xlabel(label)
        ax.set_ylabel("spectral radiance (W m$^{-2}$ sr$^{-1}$ nm$^{-1}$)")
        ax.set_title("solar %s, sun 30$^\\circ$, rural" % ("almucantar" if curve == "almucantar" else "vertical"))
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend()
    save(fig, "profiles.png")
    if worst_z > 4.0:
        failures.append("profiles: fast path vs reference mode %.1f standard errors apart" % worst_z)
    return worst_z


def spectra():
    zen, direct = rows("zenith_spectra.csv"), rows("direct_spectra.csv")
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    for b in ("none", "rural", "urban"):
        sel = [r for r in zen if r["biome"] == b]
        axes[0].plot([number(r["wavelength_nm"]) for r in sel], [number(r["zenith_radiance"]) for r in sel], label=b)
        sel = [r for r in direct if r["biome"] == b]
        axes[1].plot([number(r["wavelength_nm"]) for r in sel], [number(r["direct_normal_irradiance"]) for r in sel],
                     "o-", ms=3, label=b)
    axes[0].set_title("zenith radiance, sun 30$^\\circ$")
    axes[0].set_ylabel("W m$^{-2}$ sr$^{-1}$ nm$^{-1}$")
    axes[1].set_title("direct normal irradiance, sun 30$^\\circ$")
    axes[1].set_ylabel("W m$^{-2}$ nm$^{-1}$")
    for ax in axes:
        ax.set_xlabel("wavelength (nm)")
        ax.grid(True, alpha=0.3)
        ax.legend()
    save(fig, "spectra.png")


def astm():
    data = rows("astm_g173.csv")
    lam = [number(r["wavelength_nm"]) for r in data]
    fig, axes = plt.subplots(2, 1, figsize=(8, 6.5), sharex=True, gridspec_kw={"height_ratios": [2, 1]})
    for key, name, mark in (("direct_circumsolar", "direct normal + circumsolar", "o"),
                            ("global_tilt", "global, 37$^\\circ$ tilt", "s")):
        ours = [number(r[key]) for r in data]
        ref = [number(r["astm_" + key]) for r in data]
        line, = axes[0].plot(lam, ref, "-", label="ASTM G173-03 " + name)
        axes[0].plot(lam, ours, mark, color=line.get_color(), ms=4, label="firmament " + name)
        axes[1].plot(lam, [100 * (o / r - 1) for o, r in zip(ours, ref)], mark + "-", color=line.get_color(), ms=4,
                     label=name)
    axes[0].set_ylabel("W m$^{-2}$ nm$^{-1}$")
    axes[0].set_title("air mass 1.5 (ASTM G173-03 state)")
    axes[0].legend(fontsize=8)
    axes[1].axhspan(-3, 3, color="0.9")
    axes[1].set_ylabel("residual (%)")
    axes[1].set_xlabel("wavelength (nm)")
    axes[1].legend(fontsize=8)
    for ax in axes:
        ax.grid(True, alpha=0.3)
    save(fig, "astm_g173.png")
    direct = [abs(number(r["direct_circumsolar"]) / number(r["astm_direct_circumsolar"]) - 1) for r in data]
    band = sum(number(r["global_tilt"]) for r in data) / sum(number(r["astm_global_tilt"]) for r in data) - 1
    if max(direct) > 0.03:
        failures.append("ASTM G173 direct normal off by %.1f %%" % (100 * max(direct)))
    if abs(band) > 0.08:
        failures.append("ASTM G173 global tilt off by %.1f %% over the band" % (100 * band))
    return max(direct), band, data


def illuminance():
    data = rows("illuminance.csv")
    fig, ax = plt.subplots(figsize=(8, 4.5))
    for b, style in (("rural", "-"), ("urban", "--")):
        sel = [r for r in data if r["biome"] == b]
        e = [number(r["sun_elevation_deg"]) for r in sel]
        for key, name in (("global_horizontal_lux", "global"), ("direct_horizontal_lux", "direct"),
                          ("diffuse_horizontal_lux", "diffuse")):
            ax.semilogy(e, [max(number(r[key]), 1e-6) for r in sel], style, label="%s %s" % (b, name))
    # the published check point: ASTM G173-03's direct normal spectrum integrated with V(lambda), on
    # the horizontal (tests/physics/test_astm_g173.c writes ours and the standard's)
    lux_rows = {r["quantity"]: r for r in rows("astm_g173_lux.csv")}
    point = lux_rows["direct_horizontal"]
    e_astm = number(point["sun_elevation_deg"])
    ax.semilogy([e_astm], [number(point["astm_lux"])], "k*", ms=11, label="ASTM G173-03 direct (AM1.5)")
    ax.semilogy([e_astm], [number(point["firmament_lux"])], "rx", ms=9, label="firmament, same state")
    # clear evenings, AMS Glossary of Meteorology ("civil twilight", "astronomical twilight"): 3.5-2 lux
    # at -6, about 0.008 lux at -12, and at -18 about 6e-4 lux of which scattered sunlight is the
    # smaller part (the rest starlight and airglow, not modelled)
    ax.semilogy([-6, -6], [2.0, 3.5], "k-", lw=3, label="AMS glossary, clear evening")
    ax.semilogy([-12], [0.008], "ks", ms=6)
    ax.semilogy([-18], [6e-4], "kv", ms=7, label="AMS: all night light (sun part below)")
    ax.set_xlabel("sun elevation (deg)")
    ax.set_ylabel("horizontal illuminance (lux)")
    ax.set_ylim(1e-5, 2e5)
    ax.set_title("horizontal illuminance against sun elevation")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, ncol=2)
    save(fig, "illuminance.png")
    for key, bound in (("direct_normal", 0.03), ("global_tilt_37", 0.08)):
        r = lux_rows[key]
        if abs(number(r["firmament_lux"]) / number(r["astm_lux"]) - 1) > bound:
            failures.append("ASTM G173 %s illuminance off by more than %g %%" % (key, 100 * bound))
    return data, lux_rows


def aod():
    data = rows("aod_spectra.csv")
    fig, ax = plt.subplots(figsize=(8, 4.8))
    table = []
    for b in sorted({r["biome"] for r in data}):
        sel = [r for r in data if r["biome"] == b]
        lam = [number(r["wavelength_nm"]) for r in sel]
        tau = [number(r["aerosol_optical_depth"]) for r in sel]
        line, = ax.semilogy(lam, tau, label=b)
        if b in OPAC_BOUNDARY_LAYER:
            ax.plot([550], [OPAC_BOUNDARY_LAYER[b]], "x", color=line.get_color(), ms=8)
        t440 = next(t for l, t in zip(lam, tau) if l == 440)
        t550 = next(t for l, t in zip(lam, tau) if l == 550)
        t700 = next(t for l, t in zip(lam, tau) if l == 700)
        table.append((b, t550, -math.log(t700 / t440) / math.log(700 / 440)))
        reported = number(sel[0]["reported_aod550"])
        if abs(t550 / reported - 1) > 0.01:
            failures.append("%s: AOD(550) of the rendered profiles %.4f, reported %.4f" % (b, t550, reported))
    ax.set_xlabel("wavelength (nm)")
    ax.set_ylabel("aerosol optical depth (vertical)")
    ax.set_title("aerosol optical depth, turbidity 1 (x: OPAC boundary layer alone, PHYSICS.md 5.3)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, ncol=2)
    save(fig, "aod.png")
    return table


worst_z = profiles()
spectra()
worst_direct, band_global, astm_rows = astm()
illum, astm_lux = illuminance()
aod_table = aod()


def lux(biome, e):
    """Global and diffuse horizontal lux at the computed elevation nearest e, and that elevation."""
    r = min((r for r in illum if r["biome"] == biome), key=lambda r: abs(number(r["sun_elevation_deg"]) - e))
    return number(r["global_horizontal_lux"]), number(r["diffuse_horizontal_lux"]), number(r["sun_elevation_deg"])


lines = ["# Validation report", "",
         "Generated by `tests/validate` (%s). Every number here is also a check: the command fails when "
         "one leaves its tolerance, the same as in the test that owns it." % VERSION, "",
         "## Sky radiance along the solar almucantar and the solar vertical", "",
         "![profiles](profiles.png)", "",
         "Lines: the fast path (final quality, a 1024 x 512 monochromatic map, interpolated). Points: the "
         "reference mode (per-direction path tracing, no table) with two standard errors. Largest "
         "difference: %.1f combined standard deviations (the reference's standard error and 1%% for the "
         "map's interpolation between pixel centres; bound 4)." % worst_z, "",
         "## Zenith radiance and direct sunlight spectra", "",
         "![spectra](spectra.png)", "",
         "Sun 30 degrees, ozone 300 DU, without aerosols and with the rural and urban biomes.", "",
         "## A published reference spectrum: ASTM G173-03", "",
         "![astm](astm_g173.png)", "",
         "The standard's air-mass-1.5 state (sun zenith 48.19 degrees, U.S. Standard 1976, 343.8 DU, rural "
         "aerosol with optical depth 0.084 at 500 nm at 46%% humidity; `tests/physics/test_astm_g173.c`). "
         "Direct normal plus the circumsolar sky within 2.9 degrees: worst residual %.1f%% (bound 3%%). "
         "Global irradiance on the 37 degree tilted surface: %+.1f%% over the band (bound 8%%), largest at "
         "400 nm where the excess is all diffuse light (the direct beam agrees there to 0.2%%). Bands of "
         "water vapour and oxygen, which the model leaves out, are not compared." % (100 * worst_direct,
                                                                                    100 * band_global), "",
         "| nm | direct + circumsolar | ASTM | residual | global tilt | ASTM | residual |",
         "|---:|---:|---:|---:|---:|---:|---:|"]
for r in astm_rows:
    d, ad, g, ag = (number(r[k]) for k in ("direct_circumsolar", "astm_direct_circumsolar", "global_tilt",
                                           "astm_global_tilt"))
    lines.append("| %s | %.4f | %.4f | %+.2f%% | %.4f | %.4f | %+.2f%% |" % (r["wavelength_nm"], d, ad,
                                                                          100 * (d / ad - 1), g, ag,
                                                                          100 * (g / ag - 1)))
g30, d30, e30 = lux("rural", 30)
g90, d90, e90 = lux("rural", 90)
lines += ["", "## Horizontal illuminance against sun elevation", "",
          "![illuminance](illuminance.png)", "",
          "Direct from the disk-integrated transmittance, diffuse integrated from a 64 x 32 map at preview "
          "quality. Rural: global %.0f lux and diffuse %.0f lux with the sun at %g degrees, %.0f and %.0f "
          "at %g degrees." % (g30, d30, e30, g90, d90, e90), "",
          "Check against published values (the star): ASTM G173-03's spectra integrated with the CIE 1931 "
          "luminous efficiency, against a colour sky in the standard's state (`tests/physics/test_astm_g173.c`): "
          "direct normal plus circumsolar %.0f lux (ASTM %.0f, %+.1f%%, bound 3%%), global on the 37 degree "
          "tilt %.0f lux (ASTM %.0f, %+.1f%%, bound 8%%); the star is the direct part on the horizontal "
          "(times the cosine of the 48.19 degree zenith). The standard's water-vapour and oxygen bands, "
          "which the model leaves out, lower its values a little."
          % tuple(v for key in ("direct_normal", "global_tilt_37")
                  for v in (number(astm_lux[key]["firmament_lux"]), number(astm_lux[key]["astm_lux"]),
                            100 * (number(astm_lux[key]["firmament_lux"]) / number(astm_lux[key]["astm_lux"]) - 1))), "",
          "Twilight against the AMS Glossary of Meteorology's clear evening (entries \"civil twilight\" and "
          "\"astronomical twilight\"; the squares and bar): rural %.3g lux at sun %g (glossary 3.5-2), %.3g lux "
          "at %g (about 0.008) and %.2g lux at %g, where the glossary gives about 6e-4 lux in all, scattered "
          "sunlight being less than starlight and airglow (not modelled). The model also leaves out the "
          "refraction of the grazing sunlight. `tests/physics/test_twilight.c` checks -6, -12 and -18 within "
          "a factor 2 of those values." % (lux("rural", -6)[1], lux("rural", -6)[2], lux("rural", -12)[1],
                                            lux("rural", -12)[2], lux("rural", -18)[1], lux("rural", -18)[2]), "",
          "## Aerosol optical depth per biome", "",
          "![aod](aod.png)", "",
          "| biome | AOD 550 | Ångström 440-700 |", "|---|---:|---:|"]
lines += ["| %s | %.3f | %.2f |" % row for row in aod_table]
lines += ["", "Crosses: OPAC's typical boundary-layer mixtures at the biome's default humidity; each biome "
          "adds a free troposphere and a stratospheric layer on top (`tests/physics/test_aerosol.c` checks "
          "both parts).", ""]
with open(os.path.join(OUT, "README.md"), "w") as f:
    f.write("\n".join(lines))
if failures:
    sys.exit("validation failed:\n  " + "\n  ".join(failures))
