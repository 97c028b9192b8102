//! The second-order part of a derivative table, small enough to move
//! around cheaply in the per-cycle Newton iterations.
use super::surface::SurfaceDerivs;
use crate::math::{Mat3, Point3, Vec2, Vec3};

/// A surface point with its derivatives to second order at one parameter.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Jet2 {
    /// `[S, Su, Sv, Suu, Suv, Svv]`.
    pub d: [Vec3; 6],
}

impl From<&SurfaceDerivs> for Jet2 {
    #[inline]
    fn from(s: &SurfaceDerivs) -> Jet2 {
        let t = &s.d;
        Jet2 {
            d: [t[0][0], t[1][0], t[0][1], t[2][0], t[1][1], t[0][2]],
        }
    }
}

impl From<Jet2> for SurfaceDerivs {
    /// A table holding the jet (third derivatives zero).
    fn from(j: Jet2) -> SurfaceDerivs {
        let mut d = [[Vec3::zeros(); 4]; 4];
        [d[0][0], d[1][0], d[0][1], d[2][0], d[1][1], d[0][2]] = j.d;
        SurfaceDerivs { d }
    }
}

impl Jet2 {
    /// `S(u, v)`.
    #[inline]
    pub fn point(&self) -> Point3 {
        Point3::from(self.d[0])
    }
    /// `dS/du`.
    #[inline]
    pub fn su(&self) -> Vec3 {
        self.d[1]
    }
    /// `dS/dv`.
    #[inline]
    pub fn sv(&self) -> Vec3 {
        self.d[2]
    }
    /// `d2S/du2`.
    #[inline]
    pub fn suu(&self) -> Vec3 {
        self.d[3]
    }
    /// `d2S/dudv`.
    #[inline]
    pub fn suv(&self) -> Vec3 {
        self.d[4]
    }
    /// `d2S/dv2`.
    #[inline]
    pub fn svv(&self) -> Vec3 {
        self.d[5]
    }

    /// The jet of `x -> m x + t` applied to the surface.
    #[inline]
    pub fn mapped(&self, m: &Mat3, t: Vec3) -> Jet2 {
        let mut out = Jet2 {
            d: self.d.map(|v| m * v),
        };
        out.d[0] += t;
        out
    }

    /// The jet moved by `delta` in the parameters by Taylor expansion
    /// (point to second order, first derivatives to first order, second
    /// derivatives unchanged).
    #[inline]
    pub fn taylor(&self, delta: Vec2) -> Jet2 {
        let mut out = *self;
        out.advance(delta);
        out
    }

    /// The point of [`Self::taylor`] alone.
    #[inline]
    pub fn taylor_point(&self, delta: Vec2) -> Point3 {
        let (du, dv) = (delta.x, delta.y);
        let [p, su, sv, suu, suv, svv] = self.d;
        let quad = (suu * (du * du) + suv * (2.0 * du * dv) + svv * (dv * dv)) * 0.5;
        Point3::from(p + su * du + sv * dv + quad)
    }

    /// [`Self::taylor`] in place.
    #[inline]
    pub fn advance(&mut self, delta: Vec2) {
        let (du, dv) = (delta.x, delta.y);
        let point = self.taylor_point(delta);
        let [_, su, sv, suu, suv, svv] = self.d;
        self.d[0] = point.coords;
        self.d[1] = su + suu * du + suv * dv;
        self.d[2] = sv + suv * du + svv * dv;
    }
}
