use super::*;
use crate::math::Point3;
use rand::{RngExt, SeedableRng};

/// The upper bound [`max_curvature`] compares with `enough`: the
/// smaller of the middle bound and the samples' bound.
fn curvature_bound(seg: &CubicSegment, n: usize) -> f64 {
    middle_bound(seg).1.min(Samples::take(seg, n).bound)
}

/// Random segments like the path's and harder ones: chords of 0.2 to
/// 1 mm in random directions, end second derivatives from gentle to
/// sharp (radii down to ~0.2 mm), among them S-shapes (opposite ends)
/// and near-circles (almost equal ends, nearly constant curvature).
fn random_segments(seed: u64, count: usize) -> Vec<CubicSegment> {
    let mut rng = rand::rngs::ChaCha8Rng::seed_from_u64(seed);
    let mut unit = move || {
        let v = Vec3::new(rng.random(), rng.random(), rng.random());
        (v - Vec3::repeat(0.5)) * 2.0
    };
    (0..count)
        .map(|k| {
            let d = unit().try_normalize(1e-3).unwrap_or(Vec3::x());
            let h = 0.2 + 0.8 * unit()[0].abs();
            let scale = [0.02, 0.2, 2.0, 8.0][k % 4];
            let m0 = unit() * scale;
            let m1 = match k % 3 {
                0 => unit() * scale,
                1 => -m0 + unit() * (0.01 * scale),
                _ => m0 + unit() * (0.01 * scale),
            };
            CubicSegment::from_moments(Point3::origin(), d, h, m0, m1, 4)
        })
        .collect()
}

/// Curvature at `count + 1` evenly spaced parameters of `[lo, hi]`.
fn dense(seg: &CubicSegment, lo: f64, hi: f64, count: usize) -> Vec<f64> {
    (0..=count)
        .map(|i| seg.curvature(lo + (hi - lo) * i as f64 / count as f64))
        .collect()
}

/// The golden-section search that reuses a kept point gives exactly
/// the old search's maximum (with the ends, which the old one
/// evaluated too) with about a sixth fewer evaluations.
#[test]
fn golden_reuse_changes_nothing() {
    let (mut old_evals, mut new_evals) = (0, 0);
    for seg in random_segments(11, 300) {
        let h = seg.param_len();
        let count = std::cell::Cell::new(0);
        let f = |u: f64| {
            count.set(count.get() + 1);
            seg.curvature(u)
        };
        let old = reference::golden_max(f, 0.25 * h, 0.5 * h, 40);
        old_evals += count.replace(0);
        let new = golden_max(f, 0.25 * h, 0.5 * h, 40);
        new_evals += count.get();
        let ends = seg.curvature(0.25 * h).max(seg.curvature(0.5 * h));
        assert_eq!(new.max(ends).to_bits(), old.to_bits());
    }
    assert!(new_evals * 10 < old_evals * 9, "{new_evals} of {old_evals}");
}

/// Both bounds are above the curvature everywhere on the segment (2000
/// evenly spaced evaluations), on random segments.
#[test]
fn bounds_hold_everywhere() {
    let mut finite = 0;
    for (k, seg) in random_segments(5, 3000).iter().enumerate() {
        let most = dense(seg, 0.0, seg.param_len(), 2000)
            .into_iter()
            .fold(0.0, f64::max);
        let (middle, sampled) = (middle_bound(seg).1, Samples::take(seg, 8).bound);
        assert!(
            middle >= most && sampled >= most,
            "case {k}: {most} {middle} {sampled}"
        );
        finite += usize::from(middle.is_finite() && sampled.is_finite());
    }
    assert!(finite > 2000, "{finite} finite");
}

/// Where the slope's sign is proved on an interval, the curvature at
/// 1000 evenly spaced points of it is monotone (to its rounding); the
/// proof succeeds for most sample intervals.
#[test]
fn proved_slope_sign_is_monotone() {
    let mut proved = 0;
    let segs = random_segments(3, 1000);
    for (k, seg) in segs.iter().enumerate() {
        let slope = Slope::new(seg);
        for j in 0..8 {
            let (lo, hi) = (sample_at(seg, j, 8), sample_at(seg, j + 1, 8));
            if !slope.keeps_sign(lo, hi) {
                continue;
            }
            proved += 1;
            let ks = dense(seg, lo, hi, 1000);
            let tol = 1e-13 * ks.iter().fold(0.0, |a: f64, b| a.max(*b));
            let rises = ks.windows(2).all(|w| w[1] >= w[0] - tol);
            let falls = ks.windows(2).all(|w| w[1] <= w[0] + tol);
            assert!(rises || falls, "case {k} interval {j}");
        }
    }
    assert!(proved > 8 * segs.len() / 2, "{proved} proved");
}

/// Against the old maximisation, kept as [`reference::max_curvature`]:
/// on random segments, for commanded speeds of 20 to 200 mm/s and
/// chord-angle radii from 0.3 mm to none, the segment's largest speed
/// `min(v_cmd, sqrt(a_lat min(1 / k, R_angle)))` moves by at most the
/// speed tolerance of the planning (and mostly not at all).
#[test]
fn speed_as_before_on_random_segments() {
    let opts = crate::host::path::SpeedOptions::default();
    let mut rng = rand::rngs::ChaCha8Rng::seed_from_u64(17);
    let (mut exact, mut limited, mut refined, mut total) = (0, 0, 0, 0);
    for seg in random_segments(13, 3000) {
        let v_cmd = [20.0, 80.0, 200.0][total % 3];
        let r_angle = match total % 4 {
            0 => f64::INFINITY,
            _ => 0.3 * 100f64.powf(rng.random::<f64>()),
        };
        let enough = (opts.a_lat_mm_s2 / (v_cmd * v_cmd)).max(1.0 / r_angle);
        let v = |k: f64| {
            let r_curv = if k > 0.0 { 1.0 / k } else { f64::INFINITY };
            v_cmd.min((opts.a_lat_mm_s2 * r_curv.min(r_angle)).sqrt())
        };
        let s = opts.curvature_samples;
        let it = opts.curvature_refine_iters;
        let old = v(reference::max_curvature(&seg, s, it, enough));
        let new = v(max_curvature(&seg, s, it, enough));
        assert!((new - old).abs() <= opts.speed_tol_mm_s, "{new} {old}");
        exact += usize::from(new.to_bits() == old.to_bits());
        limited += usize::from(old < v_cmd);
        let k_ref = reference::max_curvature(&seg, s, it, 0.0);
        let by_curvature = v(k_ref) < v_cmd.min((opts.a_lat_mm_s2 * r_angle).sqrt());
        let interior = k_ref > reference::max_curvature(&seg, s, 0, 0.0);
        refined += usize::from(by_curvature && interior);
        total += 1;
    }
    assert!(limited > total / 4, "{limited} limited");
    assert!(refined > total / 5, "{refined} limited inside a bracket");
    assert!(exact > total * 99 / 100, "{exact} of {total} exact");
}

/// Random short cubics like the path's (chord ~0.5 mm, radii from
/// ~0.5 mm up): the bound is above the refined largest curvature, and
/// whenever the refinement is skipped the refined value would have
/// stayed below `enough` too, so the speed limit cannot change.
#[test]
fn skipped_refinement_could_not_have_limited_the_speed() {
    let mut rng = rand::rngs::ChaCha8Rng::seed_from_u64(7);
    let mut v =
        |s: f64| Vec3::new(rng.random(), rng.random(), rng.random()) * s - Vec3::repeat(s / 2.0);
    let enough = 1000.0 / (80.0 * 80.0);
    let mut skipped = 0;
    for k in 0..2000 {
        let scale = [0.02, 0.2, 2.0][k % 3];
        let seg = CubicSegment::from_moments(
            Point3::origin(),
            Vec3::new(1.0, 0.0, 0.0),
            0.5,
            v(scale),
            v(scale),
            4,
        );
        let refined = max_curvature(&seg, 8, 40, 0.0);
        assert!(curvature_bound(&seg, 8) >= refined, "case {k}");
        let got = max_curvature(&seg, 8, 40, enough);
        if curvature_bound(&seg, 8) <= enough * (1.0 - SKIP_MARGIN) {
            skipped += 1;
            assert!(got <= refined && refined < enough, "case {k}: {refined}");
        } else {
            assert_eq!(got, refined, "case {k}");
        }
    }
    assert!(skipped > 100, "{skipped} skipped");
}
