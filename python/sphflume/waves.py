"""Wave analysis of a run's gauges (issue 59): spectra, zero-crossing statistics, incident and
reflected waves from three gauges, overtopping discharge; figures and a JSON report in one call.

    import sphflume.waves as W
    res = W.analyse("output/irregular", depth=0.5, reflection=["eta_1", "eta_2", "eta_3"])

jonswap(f, fp, gamma) is the target shape the paddle samples. Every function takes plain numpy arrays too (times in s, elevations in m), so that lab records and
other codes' gauges go through the same analysis. Methods:
  spectrum         Welch's averaged periodogram (Hann windows, half overlap; Welch 1967) of the
                   elevation about its mean, one-sided, in m²/Hz, scaled so that Σ S Δf is the
                   record's variance (Parseval; 8 windows alone scatter by ±3 % in m0).
  spectral_stats   Hm0 = 4 sqrt(m0), Tp = 1/f at the spectrum's peak (refined by a parabola through
                   the peak's three bins), Tm-1,0 = m-1/m0 (EurOtop's period), Tm01, Tm02.
  zero_crossing    waves between downward zero crossings of the elevation about its mean (IAHR
                   1989 list of sea-state parameters): H1/3 (mean of the highest third), Hmax,
                   H_mean and the mean period Tz.
  reflection       Mansard & Funke (1980): at each frequency, the incident and reflected complex
                   amplitudes that best fit the three gauges' Fourier coefficients in least
                   squares, B_p = Z_I exp(−i k x_p) + Z_R exp(+i k x_p), k from linear dispersion;
                   frequencies where the gauges' spacings are near a multiple of half a wavelength
                   (the fit is singular) are left out. K_r = sqrt(E_R/E_I) over the band.
  overtopping      the volume past the crest, V(t) − V(0), and the mean discharge q over a window.
"""
import json
import os

import numpy as np

G = 9.81


def _uniform(t, eta):
    """The record on an even time grid at its median spacing (linear interpolation)."""
    t = np.asarray(t, float)
    eta = np.asarray(eta, float)
    ok = np.isfinite(t) & np.isfinite(eta)
    t, eta = t[ok], eta[ok]
    if len(t) < 8:
        raise ValueError("a record of at least 8 finite samples")
    dt = float(np.median(np.diff(t)))
    tu = np.arange(t[0], t[-1] + 0.5 * dt, dt)
    return tu, np.interp(tu, t, eta), dt


def wave_number(f, depth, g=G):
    """k of linear waves of frequency f [Hz] in depth h: ω² = g k tanh(k h) (Newton, vectorised)."""
    w = 2 * np.pi * np.atleast_1d(np.asarray(f, float))
    k = np.maximum(w * w / g, w / np.sqrt(g * depth))
    for _ in range(60):
        th = np.tanh(k * depth)
        fk = g * k * th - w * w
        dk = fk / (g * th + g * k * depth * (1 - th * th))
        k = k - dk
        if np.all(np.abs(dk) <= 1e-14 * np.maximum(k, 1e-300)):
            break
    return k


def jonswap(f, fp, gamma=3.3):
    """The unscaled JONSWAP shape at f [Hz] for peak frequency fp (Goda 2000 §2.3; sigma 0.07/0.09; gamma = 1:
    Pierson-Moskowitz), as the paddle's irregular law samples it (boundaries/wave_spectrum.cpp); 0 at f <= 0."""
    f = np.asarray(f, float)
    out = np.zeros_like(f)
    ok = f > 0
    r = fp / f[ok]
    s = np.where(f[ok] <= fp, 0.07, 0.09)
    out[ok] = f[ok] ** -5 * np.exp(-1.25 * r ** 4) * gamma ** np.exp(-0.5 * ((f[ok] - fp) / (s * fp)) ** 2)
    return out


def spectrum(t, eta, segment=None):
    """(f [Hz], S [m²/Hz]) by Welch's method. `segment`: samples per window (default: the record in
    8 half-overlapping windows, a power of two no longer than the record)."""
    _, y, dt = _uniform(t, eta)
    y = y - y.mean()
    n = len(y)
    if segment is None:
        segment = 2 ** int(np.floor(np.log2(max(16, 2 * n // 9))))
    segment = int(min(segment, n))
    step = segment // 2
    win = np.hanning(segment)
    scale = 1.0 / (np.sum(win ** 2) / dt)  # one-sided density: Σ S Δf = variance
    acc = None
    count = 0
    for s in range(0, n - segment + 1, step):
        seg = y[s:s + segment]
        seg = (seg - seg.mean()) * win
        p = np.abs(np.fft.rfft(seg)) ** 2 * scale
        acc = p if acc is None else acc + p
        count += 1
    S = acc / count
    S[1:-1 if segment % 2 == 0 else None] *= 2.0
    f = np.fft.rfftfreq(segment, dt)
    # the windows weight the record unevenly (the ends less): a few segments' estimate of the
    # variance scatters by several per cent, so the shape is scaled to the record's own variance
    S *= float(np.mean(y * y)) / float(np.sum(S) * (f[1] - f[0]))
    return f, S


def spectral_stats(f, S, fmin=None, fmax=None):
    """Hm0, Tp, Tm-1,0, Tm01, Tm02 of a spectrum (over [fmin, fmax] when given)."""
    f = np.asarray(f, float)
    S = np.asarray(S, float)
    band = f > 0
    if fmin is not None:
        band &= f >= fmin
    if fmax is not None:
        band &= f <= fmax
    ff, SS = f[band], S[band]
    df = float(np.median(np.diff(f)))
    m = {p: float(np.sum(SS * ff ** p) * df) for p in (-1, 0, 1, 2)}
    i = int(np.argmax(SS))
    fp = ff[i]
    if 0 < i < len(SS) - 1:  # a parabola through the peak's bins
        a, b, c = SS[i - 1], SS[i], SS[i + 1]
        den = a - 2 * b + c
        if den < 0:
            fp = ff[i] + 0.5 * df * (a - c) / den
    return {"Hm0": 4 * np.sqrt(m[0]), "Tp": 1 / fp, "Tm-1,0": m[-1] / m[0], "Tm01": m[0] / m[1],
            "Tm02": float(np.sqrt(m[0] / m[2])), "m0": m[0]}


def zero_crossing(t, eta):
    """Waves between downward zero crossings of η about its mean: dict with the heights H and
    periods T of each wave and H1/3, Hmax, Hmean, Tz, N."""
    tu, y, _ = _uniform(t, eta)
    y = y - y.mean()
    down = np.where((y[:-1] > 0) & (y[1:] <= 0))[0]
    # crossing times, linearly interpolated
    tc = tu[down] + (tu[down + 1] - tu[down]) * y[down] / (y[down] - y[down + 1])
    H, T = [], []
    for a, b, ta, tb in zip(down[:-1], down[1:], tc[:-1], tc[1:]):
        seg = y[a + 1:b + 1]
        H.append(float(seg.max() - seg.min()))
        T.append(float(tb - ta))
    H = np.array(H)
    T = np.array(T)
    if len(H) == 0:
        return {"H": H, "T": T, "N": 0, "H1/3": np.nan, "Hmax": np.nan, "Hmean": np.nan, "Tz": np.nan}
    hs = np.sort(H)[::-1]
    third = max(1, len(hs) // 3)
    return {"H": H, "T": T, "N": int(len(H)), "H1/3": float(hs[:third].mean()), "Hmax": float(hs[0]),
            "Hmean": float(H.mean()), "Tz": float(T.mean())}


def reflection(t, etas, xs, depth, fmin=None, fmax=None, g=G):
    """Incident and reflected waves from three (or more) gauges at xs along the flume (Mansard &
    Funke 1980), over the record's common span. Returns dict: f, S_I, S_R (spectra of the incident
    and reflected waves, m²/Hz), Hm0_I, Hm0_R, Kr, and the frequencies used."""
    etas = [np.asarray(e, float) for e in etas]
    xs = np.asarray(xs, float)
    if len(etas) < 3 or len(etas) != len(xs):
        raise ValueError("three or more gauges, with their x")
    ys = []
    for e in etas:
        tu, y, dt = _uniform(t, e)
        ys.append(y - y.mean())
    n = min(len(y) for y in ys)
    ys = np.array([y[:n] for y in ys])
    B = np.fft.rfft(ys, axis=1) / n  # η = Σ 2 Re(B e^{iωt}) for 0 < f < Nyquist
    f = np.fft.rfftfreq(n, dt)
    df = f[1] - f[0]
    sel = f > 0
    if fmin is not None:
        sel &= f >= fmin
    if fmax is not None:
        sel &= f <= fmax
    k = np.zeros_like(f)
    k[f > 0] = wave_number(f[f > 0], depth, g)
    ZI = np.zeros(len(f), complex)
    ZR = np.zeros(len(f), complex)
    used = np.zeros(len(f), bool)
    for j in np.where(sel)[0]:
        A = np.column_stack([np.exp(-1j * k[j] * xs), np.exp(1j * k[j] * xs)])
        # singular where every spacing is a multiple of half a wavelength: the columns align
        s = np.linalg.svd(A, compute_uv=False)
        if s[-1] < 0.3 * s[0]:
            continue
        z, *_ = np.linalg.lstsq(A, B[:, j], rcond=None)
        ZI[j], ZR[j] = z
        used[j] = True
    SI = 2 * np.abs(ZI) ** 2 / df  # one-sided density of the amplitude 2|Z|: variance 2|Z|² per bin
    SR = 2 * np.abs(ZR) ** 2 / df
    EI = float(np.sum(SI[used]) * df)
    ER = float(np.sum(SR[used]) * df)
    return {"f": f, "S_I": SI, "S_R": SR, "used": used, "Hm0_I": 4 * np.sqrt(EI), "Hm0_R": 4 * np.sqrt(ER),
            "Kr": float(np.sqrt(ER / EI)) if EI > 0 else np.nan}


def overtopping(t, volume, t0=None, t1=None):
    """The overtopped volume V(t) − V(t_start) per metre of crest and the mean discharge q [m³/s/m]
    over [t0, t1] (default: the whole record): (V(t1) − V(t0))/(t1 − t0)."""
    t = np.asarray(t, float)
    v = np.asarray(volume, float)
    t0 = t[0] if t0 is None else t0
    t1 = t[-1] if t1 is None else t1
    v0, v1 = np.interp(t0, t, v), np.interp(t1, t, v)
    return {"time": t, "volume": v - v[0], "q": float((v1 - v0) / (t1 - t0)), "window": [float(t0), float(t1)]}


def _plot_gauge(name, t, eta, f, S, zc, path, target=None):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 2, figsize=(11, 3.6))
    ax[0].plot(t, eta, lw=0.7)
    ax[0].set_xlabel("t [s]")
    ax[0].set_ylabel("η [m]")
    ax[0].set_title(f"{name}: H1/3 {zc['H1/3']:.4g} m, Hmax {zc['Hmax']:.4g} m, {zc['N']} waves")
    ax[1].plot(f, S, label="measured (Welch)")
    if target is not None:
        ax[1].plot(target[0], target[1], "k--", label="target")
    ax[1].set_xlim(0, min(f[-1], 4 * f[np.argmax(S)] if np.max(S) > 0 else f[-1]))
    ax[1].set_xlabel("f [Hz]")
    ax[1].set_ylabel("S [m²/Hz]")
    ax[1].legend()
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def analyse(run, gauges=None, depth=None, reflection_gauges=None, t0=None, t1=None, out=None, fmin=None, fmax=None):
    """Analyse a run folder (or sphflume.Run): every water_level gauge (or those named) over
    [t0, t1], the three-gauge separation when `reflection_gauges` names three gauges (needs their x
    from the gauges' .points or `xs` given as {name: x}) and every overtopping gauge. Writes
    OUT/waves.json and OUT/waves_NAME.png (default OUT = RUN/plots) and returns the report."""
    from .run import Run
    r = run if isinstance(run, Run) else Run(run)
    out = out or os.path.join(r.folder, "plots")
    os.makedirs(out, exist_ok=True)
    report = {"gauges": {}, "figures": []}
    names = gauges or r.gauge_names()

    def window(t):
        m = np.ones(len(t), bool)
        if t0 is not None:
            m &= t >= t0
        if t1 is not None:
            m &= t <= t1
        return m

    for name in names:
        g = r.gauge(name)
        if "level" in g and len(g) == 2:
            t, eta = g["time"], g["level"]
            m = window(t) & np.isfinite(eta)
            if m.sum() < 16:
                continue
            f, S = spectrum(t[m], eta[m])
            st = spectral_stats(f, S, fmin, fmax)
            zc = zero_crossing(t[m], eta[m])
            report["gauges"][name] = {k: float(v) for k, v in st.items()} | {
                "H1/3": zc["H1/3"], "Hmax": zc["Hmax"], "Hmean": zc["Hmean"], "Tz": zc["Tz"], "waves": zc["N"],
                "mean_level": float(np.mean(eta[m]))}
            report["figures"].append(_plot_gauge(name, t[m], eta[m] - np.mean(eta[m]), f, S, zc, os.path.join(out, f"waves_{name}.png")))
        elif "volume" in g:
            t = g["time"]
            m = window(t)
            ov = overtopping(t[m], g["volume"][m])
            report["gauges"][name] = {"q": ov["q"], "volume": float(ov["volume"][-1]), "window": ov["window"]}
    if reflection_gauges:
        if depth is None:
            raise ValueError("the still-water depth (depth=...) for the three-gauge separation")
        xs = [float(reflection_gauges[n]) for n in reflection_gauges] if isinstance(reflection_gauges, dict) else None
        ns = list(reflection_gauges)
        if xs is None:
            raise ValueError("reflection_gauges as {name: x} (the gauges' positions along the flume)")
        series = [r.gauge(n) for n in ns]
        t = series[0]["time"]
        m = window(t)
        rr = reflection(t[m], [s["level"][m] for s in series], xs, depth, fmin, fmax)
        report["reflection"] = {"gauges": ns, "x": xs, "Hm0_I": rr["Hm0_I"], "Hm0_R": rr["Hm0_R"], "Kr": rr["Kr"]}
    with open(os.path.join(out, "waves.json"), "w") as fjs:
        json.dump(report, fjs, indent=1)
    return report
