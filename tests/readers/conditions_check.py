"""Checks a dusty sensor sequence against the same sequence in clear air, ray by ray, with
numpy and rosbags alone: the model of docs/src/conditions.md worked out independently.

    conditions_check.py CLEAN DUSTY

Both sequences noiseless, Ouster (organized clouds: every ray has its cell), the same world,
seed and duration; DUSTY has one condition, dust (or fog) at "route": a uniform medium of
extinction alpha and backscatter beta (sequence.json's conditions) from the sensor to the
rock. For each ray, the clear-air cell gives the rock's range R0 and reflectance rho (from the
Ouster intensity, reflectance * 20000 / max(R0, 1)^2). The model says:

- the rock's return, if kept, is at R0 with its reflectance times exp(-2 alpha R0), labelled
  surface (return_kind 0): checked for every such ray;
- every other return is a particle's, labelled dust (1) or fog (2), at a range between the
  nearest range and R0: checked for every ray (a return not at the rock and not labelled a
  particle fails);
- a particle return happens with probability 1 - prod_k (1 - exp(-x / m_k)) over the range
  bins k (centres r_k = r1 + (k + 1/2) l before R0), m_k = beta l xi(r_k) exp(-2 alpha r_k) /
  r_k^2, x = max(h, s_min), h = (rho / pi) xi(R0) exp(-2 alpha R0) / R0^2: the count of
  particle returns must be within 4 standard deviations (of a sum of independent Bernoulli
  draws) of the sum of these probabilities;
- a particle return's range lies in its bin: the share of particle returns per bin must match
  a Monte Carlo of the model in numpy (20 draws a ray) within 0.03;
- a ray whose clear-air return is gone (return_kind 6) had h < s_min.

Prints one JSON line with the counts and the largest deviations.
"""
import json
import sys
from pathlib import Path

import numpy as np
from rosbags.highlevel import AnyReader


def clouds(seq):
    out = []
    with AnyReader([Path(seq) / "bag"]) as reader:
        conns = [c for c in reader.connections if c.topic == "/points"]
        for c, _, raw in reader.messages(connections=conns):
            m = reader.deserialize(raw, c.msgtype)
            names = {f.name: f.offset for f in m.fields}
            data = np.frombuffer(bytes(m.data), dtype=np.uint8).reshape(-1, m.point_step)
            rng = data[:, names["range"]:names["range"] + 4].copy().view("<u4")[:, 0] / 1000.0
            xyz = data[:, 0:12].copy().view("<f4").reshape(-1, 3).astype(np.float64)
            inten = data[:, names["intensity"]:names["intensity"] + 4].copy().view("<f4")[:, 0]
            kind = data[:, names["return_kind"]] if "return_kind" in names else np.zeros(len(data), np.uint8)
            out.append((np.linalg.norm(xyz, axis=1), rng, inten.astype(np.float64), kind))
    return out


clean_dir, dusty_dir = sys.argv[1], sys.argv[2]
meta = json.loads((Path(dusty_dir) / "sequence.json").read_text())
cond = meta["conditions"]
assert len(cond["list"]) == 1 and cond["list"][0]["at"] == "route", cond
alpha = cond["list"][0]["alpha_per_m"]
beta = cond["list"][0]["beta_per_m_sr"]
particle_kind = {"dust": 1, "fog": 2, "mist": 2}[cond["list"][0]["type"]]
rx = cond["receiver"]
r1, r2, lbin, s_min = rx["r1"], rx["r2"], rx["bin_m"], rx["s_min"]


def xi(r):
    return np.clip((r - r1) / (r2 - r1), 0.0, 1.0)


clean, dusty = clouds(clean_dir), clouds(dusty_dir)
assert len(clean) == len(dusty) and len(clean) > 0
rng = np.random.default_rng(7)
expected = variance = 0.0
observed = 0
kept = lost = 0
obs_bins, sim_bins = [], []
worst_attenuation = 0.0
for (c_norm, c_range, c_int, _), (d_norm, d_range, d_int, d_kind) in zip(clean, dusty):
    hit = c_range > 0
    R0 = c_range[hit]
    rho = c_int[hit] * np.maximum(R0, 1.0) ** 2 / 20000.0
    kind = d_kind[hit]
    dr = d_range[hit]
    di = d_int[hit]
    h = rho / np.pi * xi(R0) * np.exp(-2 * alpha * R0) / R0 ** 2
    x = np.maximum(h, s_min)
    # The bins before each ray's rock.
    nb = int(np.ceil((R0.max() - r1) / lbin)) + 1
    rk = r1 + (np.arange(nb) + 0.5) * lbin
    m = beta * lbin * xi(rk) * np.exp(-2 * alpha * rk) / rk ** 2
    valid = rk[None, :] < R0[:, None]
    with np.errstate(over="ignore", divide="ignore"):
        miss = np.where(valid, 1.0 - np.exp(-x[:, None] / m[None, :]), 1.0)
    p = 1.0 - np.prod(miss, axis=1)
    expected += p.sum()
    variance += (p * (1 - p)).sum()
    particle = kind == particle_kind
    observed += int(particle.sum())
    # Every return is the rock's (surface, at R0, dimmed as the model says) or a particle's.
    surface = kind == 0
    ok_range = np.abs(dr[surface] - R0[surface]) < 2e-3
    assert ok_range.all(), f"surface returns off the rock: {np.abs(dr[surface] - R0[surface]).max()}"
    want = rho[surface] * np.exp(-2 * alpha * R0[surface]) * 20000.0 / np.maximum(R0[surface], 1.0) ** 2
    rel = np.abs(di[surface] - want) / np.maximum(want, 1e-9)
    worst_attenuation = max(worst_attenuation, float(rel.max(initial=0.0)))
    assert (rel < 2e-3).all(), f"attenuation off by {rel.max()}"
    assert set(np.unique(kind)) <= {0, particle_kind, 6}, np.unique(kind)
    assert ((dr[particle] >= r1 - 1e-3) & (dr[particle] <= R0[particle] + 1e-3)).all()
    gone = kind == 6
    assert (h[gone] < s_min).all(), "a return was lost above the detection floor"
    assert (dr[gone] == 0).all()
    kept += int(surface.sum())
    lost += int(gone.sum())
    obs_bins.append(np.floor((dr[particle] - r1) / lbin).astype(int))
    # Monte Carlo of the winner's bin, 20 draws a ray.
    for _ in range(20):
        e = rng.exponential(1.0, size=(len(R0), nb)) * m[None, :]
        e = np.where(valid, e, 0.0)
        best = e.argmax(axis=1)
        win = e[np.arange(len(R0)), best] > x
        sim_bins.append(best[win])
obs_bins = np.concatenate(obs_bins)
sim_bins = np.concatenate(sim_bins)
sigma = np.sqrt(variance)
assert abs(observed - expected) < 4 * sigma + 1, f"{observed} particle returns, the model expects {expected:.1f} +- {sigma:.1f}"
nb = max(obs_bins.max(initial=0), sim_bins.max(initial=0)) + 1
obs_share = np.bincount(obs_bins, minlength=nb) / max(len(obs_bins), 1)
sim_share = np.bincount(sim_bins, minlength=nb) / max(len(sim_bins), 1)
worst_bin = float(np.abs(obs_share - sim_share).max())
assert worst_bin < 0.03, f"particle ranges by bin {obs_share} against the model's {sim_share}"
print(json.dumps({
    "particle_returns": observed,
    "expected": round(expected, 1),
    "sigma": round(sigma, 1),
    "surface_returns": kept,
    "lost": lost,
    "bin_shares": [round(v, 4) for v in obs_share.tolist()],
    "model_bin_shares": [round(v, 4) for v in sim_share.tolist()],
    "worst_bin_share_difference": round(worst_bin, 4),
    "worst_attenuation_error": worst_attenuation,
}))
