//! Knot vectors and B-spline basis functions (The NURBS Book, A2.1-A2.3).
use thiserror::Error;

/// Highest supported B-spline degree (basis tables live on the stack).
pub const MAX_DEGREE: usize = 15;

/// Highest derivative order the evaluators compute.
pub const MAX_DERIVATIVE: usize = 3;

/// Why a knot vector is invalid.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum KnotError {
    /// Degree 0 (piecewise constant) is not a surface we can measure.
    #[error("degree must be at least 1")]
    DegreeZero,
    /// Degree above [`MAX_DEGREE`].
    #[error("degree {degree} exceeds the supported maximum {max}", max = MAX_DEGREE)]
    DegreeTooHigh {
        /// The requested degree.
        degree: usize,
    },
    /// A knot is NaN or infinite.
    #[error("knot {index} is not finite")]
    NotFinite {
        /// Index of the knot.
        index: usize,
    },
    /// Knots must not decrease.
    #[error("knots decrease at index {index}: {prev} > {next}")]
    Decreasing {
        /// Index of the smaller, later knot.
        index: usize,
        /// The knot before it.
        prev: f64,
        /// The knot at `index`.
        next: f64,
    },
    /// Fewer than `2 (degree + 1)` knots.
    #[error("{len} knots are too few for degree {degree}: at least {need} needed")]
    TooFew {
        /// Number of knots given.
        len: usize,
        /// The degree.
        degree: usize,
        /// Minimum number of knots.
        need: usize,
    },
    /// A knot repeated more than `degree + 1` times (or an interior knot more
    /// than `degree` times), which would make the surface discontinuous.
    #[error("knot {value} at index {index} has multiplicity {mult}, more than allowed ({max})")]
    Multiplicity {
        /// Index of the first occurrence.
        index: usize,
        /// Knot value.
        value: f64,
        /// Its multiplicity.
        mult: usize,
        /// Allowed maximum there.
        max: usize,
    },
    /// The parameter domain `[knots[p], knots[n]]` is empty.
    #[error("empty parameter domain [{lo}, {hi}]")]
    EmptyDomain {
        /// Domain start.
        lo: f64,
        /// Domain end.
        hi: f64,
    },
}

/// A validated, non-decreasing knot vector with its degree.
///
/// The parameter domain is `[knots[p], knots[len - p - 1]]`; clamped and
/// unclamped vectors are both accepted.
///
/// ```
/// use cmm::geometry::KnotVector;
/// let k = KnotVector::try_new(vec![0.0, 0.0, 0.0, 1.0, 2.0, 2.0, 2.0], 2).unwrap();
/// assert_eq!(k.num_basis(), 4);
/// assert_eq!(k.domain(), (0.0, 2.0));
/// assert!(KnotVector::try_new(vec![0.0, 1.0, 0.5, 2.0], 1).is_err());
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct KnotVector {
    knots: Vec<f64>,
    degree: usize,
    /// `(knots[p], knots[len - p - 1])`, kept because every projection
    /// step asks for it.
    domain: (f64, f64),
}

impl KnotVector {
    /// Validates and wraps a knot vector.
    pub fn try_new(knots: Vec<f64>, degree: usize) -> Result<Self, KnotError> {
        check_degree(degree)?;
        check_values(&knots)?;
        let need = 2 * (degree + 1);
        if knots.len() < need {
            return Err(KnotError::TooFew {
                len: knots.len(),
                degree,
                need,
            });
        }
        check_multiplicities(&knots, degree)?;
        let (lo, hi) = (knots[degree], knots[knots.len() - degree - 1]);
        let kv = KnotVector {
            knots,
            degree,
            domain: (lo, hi),
        };
        if lo >= hi {
            return Err(KnotError::EmptyDomain { lo, hi });
        }
        Ok(kv)
    }

    /// The degree.
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// The knots.
    pub fn as_slice(&self) -> &[f64] {
        &self.knots
    }

    /// Number of basis functions (= control points in this direction).
    pub fn num_basis(&self) -> usize {
        self.knots.len() - self.degree - 1
    }

    /// Parameter domain `(start, end)`.
    pub fn domain(&self) -> (f64, f64) {
        self.domain
    }

    /// Distinct knot values inside the domain, including both ends.
    pub fn breakpoints(&self) -> Vec<f64> {
        let (lo, hi) = self.domain();
        let mut out: Vec<f64> = Vec::new();
        for &k in self.knots.iter().filter(|&&k| k >= lo && k <= hi) {
            if out.last() != Some(&k) {
                out.push(k);
            }
        }
        out
    }

    /// Multiplicity of the value `u` in the knot vector.
    pub fn multiplicity(&self, u: f64) -> usize {
        self.knots.iter().filter(|&&k| k == u).count()
    }

    /// Index `s` of the knot span containing `u` (clamped to the domain):
    /// `knots[s] <= u < knots[s + 1]`, with the last non-empty span at the end.
    pub fn find_span(&self, u: f64) -> usize {
        let p = self.degree;
        let n = self.num_basis();
        let (lo, hi) = self.domain();
        if u >= hi {
            return self.last_span(n);
        }
        if u <= lo {
            return self.first_span(p);
        }
        // partition_point: first index whose knot is > u.
        let upper = self.knots[p..=n].partition_point(|&k| k <= u) + p;
        upper - 1
    }

    fn last_span(&self, n: usize) -> usize {
        let mut s = n - 1;
        while s > self.degree && self.knots[s] >= self.knots[s + 1] {
            s -= 1;
        }
        s
    }

    fn first_span(&self, p: usize) -> usize {
        let mut s = p;
        while self.knots[s + 1] <= self.knots[p] {
            s += 1;
        }
        s
    }

    /// Values and derivatives up to order `nd` of the `p + 1` non-zero basis
    /// functions at `u` in span `span`: `out[k][r]` is the k-th derivative of
    /// `N_{span - p + r}`. `N` must be at least `p + 1`.
    pub fn basis_derivs<const N: usize>(&self, span: usize, u: f64, nd: usize) -> [[f64; N]; 4] {
        basis_derivs::<N>(&self.knots, self.degree, span, u, nd.min(MAX_DERIVATIVE))
    }
}

fn check_degree(degree: usize) -> Result<(), KnotError> {
    match degree {
        0 => Err(KnotError::DegreeZero),
        d if d > MAX_DEGREE => Err(KnotError::DegreeTooHigh { degree }),
        _ => Ok(()),
    }
}

fn check_values(knots: &[f64]) -> Result<(), KnotError> {
    if let Some(index) = knots.iter().position(|k| !k.is_finite()) {
        return Err(KnotError::NotFinite { index });
    }
    for (i, w) in knots.windows(2).enumerate() {
        if w[1] < w[0] {
            return Err(KnotError::Decreasing {
                index: i + 1,
                prev: w[0],
                next: w[1],
            });
        }
    }
    Ok(())
}

fn check_multiplicities(knots: &[f64], degree: usize) -> Result<(), KnotError> {
    let n = knots.len();
    let mut start = 0;
    while start < n {
        let value = knots[start];
        let mult = knots[start..].iter().take_while(|&&k| k == value).count();
        let at_end = start == 0 || start + mult == n;
        let max = if at_end { degree + 1 } else { degree };
        if mult > max {
            return Err(KnotError::Multiplicity {
                index: start,
                value,
                mult,
                max,
            });
        }
        start += mult;
    }
    Ok(())
}

/// Basis values and derivatives (The NURBS Book A2.2 for the values; the
/// derivatives by repeatedly raising lower-degree values with
/// `N'_{i,d+1} = (d+1) (N_{i,d} / (u_{i+d+1} - u_i) - N_{i+1,d} / (u_{i+d+2} - u_{i+1}))`,
/// reusing the reciprocal knot differences of A2.2). Fixed-size stack tables
/// of capacity `N >= p + 1`.
fn basis_derivs<const N: usize>(
    knots: &[f64],
    p: usize,
    span: usize,
    u: f64,
    nd: usize,
) -> [[f64; N]; 4] {
    let nd = nd.min(p);
    let mut inv = [[0.0; N]; N];
    let mut levels = [[0.0; N]; 4];
    let mut n = [0.0; N];
    n[0] = 1.0;
    if nd >= p {
        levels[p] = n;
    }
    let mut left = [0.0; N];
    let mut right = [0.0; N];
    for j in 1..=p {
        left[j] = u - knots[span + 1 - j];
        right[j] = knots[span + j] - u;
        let mut saved = 0.0;
        for r in 0..j {
            let den = right[r + 1] + left[j - r];
            let iv = if den != 0.0 { 1.0 / den } else { 0.0 };
            inv[j][r] = iv;
            let temp = n[r] * iv;
            n[r] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        n[j] = saved;
        if j + nd >= p {
            levels[p - j] = n;
        }
    }
    let mut out = [[0.0; N]; 4];
    out[0] = levels[0];
    for k in 1..=nd {
        let mut v = levels[k];
        for d in (p - k)..p {
            v = raise(&v, &inv[d + 1], d);
        }
        out[k] = v;
    }
    out
}

/// Derivative coefficients of degree `d + 1` from the `d + 1` values of
/// degree `d`; `inv[j]` is `1 / (u_{span+j+1} - u_{span+j-d})`.
fn raise<const N: usize>(v: &[f64; N], inv: &[f64; N], d: usize) -> [f64; N] {
    let mut w = [0.0; N];
    let scale = (d + 1) as f64;
    let mut prev = 0.0;
    for r in 0..=d {
        let cur = v[r] * inv[r];
        w[r] = scale * (prev - cur);
        prev = cur;
    }
    w[d + 1] = scale * prev;
    w
}
