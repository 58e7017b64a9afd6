#!/usr/bin/env python3
"""Lower bound on the camera position error WITHOUT alignment that any pose
estimator can reach when the world frame is known only through i.i.d. pose
priors (issue 6, target 'mean position error without alignment').

Even with perfect relative poses (and perfect metric scale from the LIDAR),
the estimate is the ground truth moved by an unknown rigid transform (the
gauge) that only the priors determine. The noise model is the synthesizer's
(src/synth/README.md): c_prior = c + e, e ~ N(0, sigma_t^2 I) per axis;
R_prior = Exp(theta a) R (world_from_cam), a uniform on the sphere, theta ~
N(0, sigma_r^2), so the rotation vector has per-axis variance sigma_r^2 / 3.

For a small gauge error g = (dtheta, dt[, ds]) the camera centre moves by
J_i g with J_i = [-[c_i]x, I(, c_i)]; the priors give the Fisher information
  F = sum_i J_i^T J_i / sigma_t^2 + N [I 0; 0 0] / sigma_w^2,
sigma_w = per-axis rotation sigma. Cramer-Rao: cov(g) >= F^-1, so camera i's
error is at best N(0, J_i F^-1 J_i^T); the script reports the expected mean
(over cameras) of its norm, and quantiles over scenes (one scene is one draw
of the gauge error). A Monte-Carlo run checks it: noisy priors are drawn from
the synthesizer's model, the weighted least-squares rigid (or similarity) fit
of the ground-truth trajectory to them (the best estimator given perfect
relative poses) is computed, and its mean position error recorded.

With --prior the same fit on the actual prior file gives the error that
estimator reaches on that scene's noise draw ("oracle").

Usage:
  pose_gauge_bound.py --gt poses_gt.txt [--prior poses_prior.txt]
      [--sigma_t 0.5] [--sigma_r_deg 5] [--trials 4000] [--seed 1]
"""
import argparse
import math

import numpy as np


def quat_to_matrix(qx, qy, qz, qw):
    q = np.array([qw, qx, qy, qz]) / np.linalg.norm([qw, qx, qy, qz])
    w, x, y, z = q
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def read_tum(path):
    """frame -> (centre, world_from_cam rotation)."""
    poses = {}
    with open(path) as f:
        for line in f:
            fields = line.split()
            if not fields or fields[0].startswith("#"):
                continue
            values = [float(v) for v in fields[1:8]]
            poses[fields[0]] = (np.array(values[:3]),
                                quat_to_matrix(*values[3:7]))
    return poses


def skew(v):
    return np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


def exp_so3(w):
    angle = np.linalg.norm(w)
    if angle < 1e-12:
        return np.eye(3) + skew(w)
    k = skew(w / angle)
    return np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * k @ k


def log_so3(r):
    cos_angle = np.clip((np.trace(r) - 1) / 2, -1.0, 1.0)
    angle = math.acos(cos_angle)
    v = np.array([r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]])
    if angle < 1e-9:
        return v / 2
    return v * angle / (2 * math.sin(angle))


def centre_jacobian(c, with_scale):
    """d(centre)/d(dtheta, dt[, ds]) for x -> (1+ds) Exp(dtheta) x + dt."""
    blocks = [-skew(c), np.eye(3)]
    if with_scale:
        blocks.append(c.reshape(3, 1))
    return np.hstack(blocks)


def fisher(centres, sigma_t, sigma_w, with_scale):
    dim = 7 if with_scale else 6
    info = np.zeros((dim, dim))
    for c in centres:
        j = centre_jacobian(c, with_scale)
        info += j.T @ j / sigma_t ** 2
    info[:3, :3] += len(centres) * np.eye(3) / sigma_w ** 2
    return info


def crlb_mean_error(centres, cov, rng, samples):
    """Distribution over scenes of the mean camera error for gauge errors
    g ~ N(0, cov) (linearised)."""
    chol = np.linalg.cholesky(cov + 1e-18 * np.eye(len(cov)))
    g = rng.standard_normal((samples, len(cov))) @ chol.T
    jac = np.stack([centre_jacobian(c, len(cov) == 7) for c in centres])
    errors = np.linalg.norm(np.einsum("nij,sj->sni", jac, g), axis=2)
    return errors.mean(axis=1)


def fit_gauge(centres, rotations, prior_centres, prior_rotations, sigma_t,
              sigma_w, with_scale, iterations=8):
    """Weighted least squares (Gauss-Newton) of x -> s R x + t applied to the
    ground truth onto the priors; returns the moved centres."""
    rot = np.eye(3)
    trans = np.zeros(3)
    scale = 1.0
    for _ in range(iterations):
        # Linearise the update x -> (1 + ds) Exp(dw) x + dt applied after
        # the current transform.
        rows = []
        residuals = []
        for c, r, pc, pr in zip(centres, rotations, prior_centres,
                                prior_rotations):
            moved = scale * rot @ c + trans
            jac = centre_jacobian(moved, with_scale)
            rows.append(jac / sigma_t)
            residuals.append((pc - moved) / sigma_t)
            rot_jac = np.zeros((3, jac.shape[1]))
            rot_jac[:, :3] = np.eye(3)
            rows.append(rot_jac / sigma_w)
            residuals.append(log_so3(pr @ (rot @ r).T) / sigma_w)
        step = np.linalg.lstsq(np.vstack(rows), np.concatenate(residuals),
                               rcond=None)[0]
        factor = 1.0 + step[6] if with_scale else 1.0
        update = exp_so3(step[:3])
        scale *= factor
        rot = update @ rot
        trans = factor * update @ trans + step[3:6]
    return np.array([scale * rot @ c + trans for c in centres])


def draw_priors(centres, rotations, sigma_t, sigma_r, rng):
    prior_centres = centres + sigma_t * rng.standard_normal(centres.shape)
    prior_rotations = []
    for r in rotations:
        axis = rng.standard_normal(3)
        axis /= np.linalg.norm(axis)
        prior_rotations.append(exp_so3(rng.normal(0.0, sigma_r) * axis) @ r)
    return prior_centres, prior_rotations


def summary(label, values):
    q = np.quantile(values, [0.05, 0.5, 0.95])
    return (f"| {label} | {values.mean():.4f} | {q[0]:.4f} | {q[1]:.4f} | "
            f"{q[2]:.4f} | {np.mean(values <= 0.03):.2f} |")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--gt", required=True)
    parser.add_argument("--prior")
    parser.add_argument("--sigma_t", type=float, default=0.5,
                        help="per-axis prior centre sigma, metres")
    parser.add_argument("--sigma_r_deg", type=float, default=5.0,
                        help="RMS prior rotation angle, degrees")
    parser.add_argument("--trials", type=int, default=2000)
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()

    gt = read_tum(args.gt)
    frames = sorted(gt)
    centres = np.array([gt[f][0] for f in frames])
    rotations = [gt[f][1] for f in frames]
    sigma_r = math.radians(args.sigma_r_deg)
    sigma_w = sigma_r / math.sqrt(3.0)
    rng = np.random.default_rng(args.seed)
    # The origin does not change the bound; centring keeps F well scaled.
    origin = centres.mean(axis=0)
    local = centres - origin

    print(f"{len(frames)} cameras, trajectory extent "
          f"{np.ptp(centres, axis=0).round(2).tolist()} m, prior sigmas "
          f"{args.sigma_t} m per axis, {args.sigma_r_deg} deg RMS angle "
          f"({math.degrees(sigma_w):.2f} deg per axis)")
    print()
    print("Mean camera position error without alignment, metres, over "
          "scenes (one scene = one draw of the prior noise):")
    print()
    print("| estimator with perfect relative poses | expected | 5% | median "
          "| 95% | P(<= 0.03 m) |")
    print("|---|---|---|---|---|---|")
    for with_scale in (False, True):
        dof = "7-DoF (scale free)" if with_scale else "6-DoF (metric scale)"
        cov = np.linalg.inv(fisher(local, args.sigma_t, sigma_w, with_scale))
        bound = crlb_mean_error(local, cov, rng, 50000)
        print(summary(f"Cramer-Rao bound, {dof}", bound))
        trials = []
        for _ in range(args.trials if not with_scale else args.trials // 4):
            pc, pr = draw_priors(centres, rotations, args.sigma_t, sigma_r,
                                 rng)
            fitted = fit_gauge(local, rotations, pc - origin, pr,
                               args.sigma_t, sigma_w, with_scale)
            trials.append(np.linalg.norm(fitted - local, axis=1).mean())
        print(summary(f"Monte-Carlo weighted LSQ fit, {dof}",
                      np.array(trials)))
    if args.prior:
        prior = read_tum(args.prior)
        pc = np.array([prior[f][0] for f in frames]) - origin
        pr = [prior[f][1] for f in frames]
        print()
        for with_scale in (False, True):
            for label, weight in (("per-axis", sigma_w),
                                  ("5 deg per axis", sigma_r)):
                if with_scale and label != "per-axis":
                    continue
                fitted = fit_gauge(local, rotations, pc, pr, args.sigma_t,
                                   weight, with_scale)
                error = np.linalg.norm(fitted - local, axis=1)
                dof = "7-DoF" if with_scale else "6-DoF"
                print(f"Oracle on {args.prior} ({dof}, rotation prior "
                      f"weight {math.degrees(weight):.2f} deg {label}): "
                      f"mean {error.mean():.4f} m, median "
                      f"{np.median(error):.4f} m, max {error.max():.4f} m")


if __name__ == "__main__":
    main()
