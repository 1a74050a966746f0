//! Stage `integrate` in lanes, its numbers: 8 f32 lanes (`F8`) and lane masks (`M8`), each
//! operation a loop over the 8 lanes with no branch, which the compiler turns into one SIMD
//! instruction (AVX2) or two (SSE2). A loop over whole lanes' computations does not vectorise
//! (its branches and calls stop it); operations this small always do.

use glam::Vec3A;
use std::ops::{Add, BitAnd, BitOr, BitXor, Div, Mul, Neg, Not, Sub};

pub const LANES: usize = 8;

#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct F8(pub [f32; LANES]);

/// A lane mask: all bits set where true.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct M8(pub [u32; LANES]);

/// 8 lanes of i32 (exponents).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct I8(pub [i32; LANES]);

macro_rules! lanewise {
    ($($t:ident, $tr:ident, $f:ident, $op:tt;)*) => {$(
        impl $tr for $t {
            type Output = $t;
            #[inline(always)]
            fn $f(self, o: $t) -> $t {
                let mut r = self;
                for i in 0..LANES {
                    r.0[i] = self.0[i] $op o.0[i];
                }
                r
            }
        }
    )*};
}

lanewise! {
    F8, Add, add, +;
    F8, Sub, sub, -;
    F8, Mul, mul, *;
    F8, Div, div, /;
    M8, BitAnd, bitand, &;
    M8, BitOr, bitor, |;
    M8, BitXor, bitxor, ^;
    I8, Add, add, +;
}

impl Neg for F8 {
    type Output = F8;
    #[inline(always)]
    fn neg(self) -> F8 {
        self.map(|x| -x)
    }
}

impl Not for M8 {
    type Output = M8;
    #[inline(always)]
    fn not(self) -> M8 {
        M8(self.0.map(|m| !m))
    }
}

impl F8 {
    #[inline(always)]
    pub fn splat(x: f32) -> F8 {
        F8([x; LANES])
    }

    #[inline(always)]
    pub fn map(self, f: impl Fn(f32) -> f32) -> F8 {
        F8(self.0.map(f))
    }

    #[inline(always)]
    fn compare(self, o: F8, f: impl Fn(f32, f32) -> bool) -> M8 {
        let mut m = M8::default();
        for i in 0..LANES {
            m.0[i] = if f(self.0[i], o.0[i]) { !0 } else { 0 };
        }
        m
    }

    #[inline(always)]
    pub fn lt(self, o: F8) -> M8 {
        self.compare(o, |a, b| a < b)
    }

    #[inline(always)]
    pub fn gt(self, o: F8) -> M8 {
        self.compare(o, |a, b| a > b)
    }

    #[inline(always)]
    pub fn ge(self, o: F8) -> M8 {
        self.compare(o, |a, b| a >= b)
    }

    #[inline(always)]
    pub fn eq(self, o: F8) -> M8 {
        self.compare(o, |a, b| a == b)
    }

    /// `a.max(b)` where neither is NaN (`maxps`' rule: `b` where either is).
    #[inline(always)]
    pub fn max(self, o: F8) -> F8 {
        let mut r = self;
        for i in 0..LANES {
            r.0[i] = if self.0[i] > o.0[i] { self.0[i] } else { o.0[i] };
        }
        r
    }

    #[inline(always)]
    pub fn min(self, o: F8) -> F8 {
        let mut r = self;
        for i in 0..LANES {
            r.0[i] = if self.0[i] < o.0[i] { self.0[i] } else { o.0[i] };
        }
        r
    }

    #[inline(always)]
    pub fn sqrt(self) -> F8 {
        self.map(f32::sqrt)
    }

    #[inline(always)]
    pub fn abs(self) -> F8 {
        F8::from_bits(self.to_bits() & M8([0x7fff_ffff; LANES]))
    }

    /// 1 with the sign of each lane.
    #[inline(always)]
    pub fn signum_bits(self) -> F8 {
        F8::from_bits((self.to_bits() & M8([0x8000_0000; LANES])) | F8::splat(1.0).to_bits())
    }

    #[inline(always)]
    pub fn to_bits(self) -> M8 {
        M8(self.0.map(f32::to_bits))
    }

    #[inline(always)]
    pub fn from_bits(b: M8) -> F8 {
        F8(b.0.map(f32::from_bits))
    }
}

impl M8 {
    /// `a` where set, else `b`.
    #[inline(always)]
    pub fn select(self, a: F8, b: F8) -> F8 {
        F8::from_bits((self & a.to_bits()) | (!self & b.to_bits()))
    }

    #[inline(always)]
    pub fn splat(x: u32) -> M8 {
        M8([x; LANES])
    }

    #[inline(always)]
    pub fn shifted_right(self, n: u32) -> M8 {
        M8(self.0.map(|x| x >> n))
    }

    #[inline(always)]
    pub fn as_i8(self) -> I8 {
        I8(self.0.map(|x| x as i32))
    }
}

impl I8 {
    #[inline(always)]
    pub fn splat(x: i32) -> I8 {
        I8([x; LANES])
    }

    #[inline(always)]
    pub fn shifted_left(self, n: u32) -> M8 {
        M8(self.0.map(|x| (x << n) as u32))
    }

    /// Each lane as a float (exact below 2²⁴).
    #[inline(always)]
    pub fn to_f8(self) -> F8 {
        F8(self.0.map(|x| x as f32))
    }
}

/// 8 lanes of 3-vectors.
#[derive(Clone, Copy, Default)]
pub struct V8 {
    pub x: F8,
    pub y: F8,
    pub z: F8,
}

impl V8 {
    #[inline(always)]
    pub fn dot(self, o: V8) -> F8 {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    #[inline(always)]
    pub fn scale(self, s: F8) -> V8 {
        V8 {
            x: self.x * s,
            y: self.y * s,
            z: self.z * s,
        }
    }

    #[inline(always)]
    pub fn plus(self, o: V8) -> V8 {
        V8 {
            x: self.x + o.x,
            y: self.y + o.y,
            z: self.z + o.z,
        }
    }

    #[inline(always)]
    pub fn select(m: M8, a: V8, b: V8) -> V8 {
        V8 {
            x: m.select(a.x, b.x),
            y: m.select(a.y, b.y),
            z: m.select(a.z, b.z),
        }
    }

    pub fn set(&mut self, i: usize, v: Vec3A) {
        (self.x.0[i], self.y.0[i], self.z.0[i]) = (v.x, v.y, v.z);
    }

    pub fn at(&self, i: usize) -> Vec3A {
        Vec3A::new(self.x.0[i], self.y.0[i], self.z.0[i])
    }

    /// `Vec3A::normalize_or_zero`'s rule (times the reciprocal length; `or` where that is not
    /// a finite positive number).
    #[inline(always)]
    pub fn normalize_or(self, or: V8) -> V8 {
        let rcp = F8::splat(1.0) / self.dot(self).sqrt();
        let usable = rcp.lt(F8::splat(f32::INFINITY)) & rcp.gt(F8::splat(0.0));
        V8::select(usable, self.scale(rcp), or)
    }
}

/// `$vis fn $name($args) -> $ret` running `$body` (an `#[inline(always)]` function of the same
/// arguments) compiled for AVX2 where the processor has it (detected when it runs, cached by
/// std), else as compiled for the target (SSE2 on every x86-64).
macro_rules! simd_dispatch {
    ($(#[$doc:meta])* $vis:vis fn $name:ident($($arg:ident: $ty:ty),*) -> $ret:ty = $body:ident) => {
        $(#[$doc])*
        $vis fn $name($($arg: $ty),*) -> $ret {
            #[cfg(target_arch = "x86_64")]
            {
                #[target_feature(enable = "avx2")]
                unsafe fn avx2($($arg: $ty),*) -> $ret {
                    $body($($arg),*)
                }
                if std::is_x86_feature_detected!("avx2") {
                    // SAFETY: the processor has AVX2, just checked.
                    return unsafe { avx2($($arg),*) };
                }
            }
            $body($($arg),*)
        }
    };
}
pub(crate) use simd_dispatch;
