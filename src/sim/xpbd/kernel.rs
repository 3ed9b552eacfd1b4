//! Projecting springs as compliant distance constraints, many at a time.
//!
//! For a spring between `a` and `b` with rest length `L`, stiffness `k` and damping `c`, one
//! XPBD projection in a substep of `h` seconds (Macklin et al. 2016, eqs. 18 and 26) moves the
//! ends by
//!
//! `Δλ = −(C + γ Ċh) / ((1 + γ)(w_a + w_b) + α̃)`, `Δx_a = w_a Δλ n`, `Δx_b = −w_b Δλ n`
//!
//! with `C = |x_a − x_b| − L`, `n` the unit vector from `b` to `a`, `α̃ = 1/(k h²)`, `γ = c/(k h)`
//! and `Ċh = n · (Δx_a − Δx_b)` the constraint's change over the substep so far. The per-spring
//! factors `w/((1 + γ)(w_a + w_b) + α̃)` are computed once (they change only with masses, pins,
//! burning and the step) and passed in as `ca`, `cb`; a dead spring has both zero.
//!
//! A compressed spring (`C < 0`) is `r` times as stiff (`r` the run's `compression`, see
//! [`BurnMaterial::compression`](crate::sim::BurnMaterial::compression)),
//! with the same damping coefficient: its compliance is `α̃ / r` and its damping factor
//! `γ / r`, so
//!
//! `Δλ = −(r C + γ Ċh) / ((r + γ)(w_a + w_b) + α̃)`,
//!
//! which is the stretched projection's numerator with `r C` for `C`, over its denominator
//! times `1 − (1 − r)(c_a + c_b)` (as `(w_a + w_b) = (c_a + c_b) × denominator`). That factor
//! is at least `r` and shares the division by `|x_a − x_b|` the projection makes anyway, so
//! a softer compression costs no array more and no division more (the dynamics phase 5 to
//! 11 % dearer in `examples/stress.rs -- --default-only`, eight alternated runs); with
//! `r = 1` it is 1 and the projection is the stretched one to
//! the bit. It is kept from 1e-6 up, so `r = 0` with no damping on a spring so stiff that
//! `c_a + c_b` rounds to 1 moves nothing instead of dividing by zero. Runs of springs with
//! `r = 1` (bending springs, and every spring of a material with linear springs) take a
//! plain form of the loop without those steps, with the same bits (the dynamics of the
//! burning cloths in `examples/stress.rs` about 3 % cheaper).
//!
//! A particle's position is split into where it was at the start of the substep, `x`, and how
//! far it has moved since, `u` (both f32): the prediction sets `u = h v`, corrections add to
//! `u`, and the new velocity is `u / h`. Small corrections keep all their digits however small
//! the step (the old form `v = (x_new − x_old) / h` lost them to round-off), and the
//! constraint's change over the substep, `u_a − u_b`, needs no velocity.
//!
//! Two shapes of loop: a lane, whose element `k` joins slot `a + k` to slot `b + k` (every
//! family of a grid, see [`lanes`](super::lanes)), written four elements at a time with no
//! branch so the compiler turns it into SIMD instructions; and springs with ends by index
//! (meshes).

/// Particle arrays for one kernel call: positions at the start of the substep `x` and the
/// displacements since `u` (three components each), all of one length.
pub(crate) struct Arrays<'a> {
    pub x: [&'a [f32]; 3],
    pub u: [&'a mut [f32]; 3],
}

/// Per-spring data of one run: rest lengths and the two correction factors.
#[derive(Clone, Copy)]
pub(crate) struct RunData<'a> {
    pub rest: &'a [f32],
    pub ca: &'a [f32],
    pub cb: &'a [f32],
    pub gamma: f32,
    /// The fraction of the stiffness that resists compression (1 for as stiff as in tension).
    pub compression: f32,
}

impl<'a> RunData<'a> {
    /// The same data with every array cut to `len` entries.
    #[inline(always)]
    fn cut(self, len: usize) -> Self {
        Self {
            rest: &self.rest[..len],
            ca: &self.ca[..len],
            cb: &self.cb[..len],
            gamma: self.gamma,
            compression: self.compression,
        }
    }
}

/// Whether a run's springs give to a push (their compression fraction is not 1): those take
/// the softer compression's form of the projection, the others the plain one, which gives
/// the same bits for them with less work (bending springs, and every spring of a material
/// with linear springs).
#[inline(always)]
fn is_soft(data: &RunData) -> bool {
    data.compression != 1.0
}

/// `N` lanes of `f32`, which the compiler keeps in one SIMD register (4: SSE, 8: AVX).
type Lanes<const N: usize> = [f32; N];

#[inline(always)]
fn load<const N: usize>(slice: &[f32], at: usize) -> Lanes<N> {
    let mut out = [0.0; N];
    out.copy_from_slice(&slice[at..at + N]);
    out
}

#[inline(always)]
fn store<const N: usize>(slice: &mut [f32], at: usize, value: Lanes<N>) {
    slice[at..at + N].copy_from_slice(&value);
}

/// The `N` values from `at` of each of three arrays (one per axis).
#[inline(always)]
fn load_axes<const N: usize, S: AsRef<[f32]>>(axes: &[S; 3], at: usize) -> [Lanes<N>; 3] {
    [
        load(axes[0].as_ref(), at),
        load(axes[1].as_ref(), at),
        load(axes[2].as_ref(), at),
    ]
}

/// `value`'s three axes stored from `at` in the three arrays.
#[inline(always)]
fn store_axes<const N: usize>(axes: &mut [&mut [f32]; 3], at: usize, value: [Lanes<N>; 3]) {
    store(axes[0], at, value[0]);
    store(axes[1], at, value[1]);
    store(axes[2], at, value[2]);
}

#[inline(always)]
fn zip<const N: usize>(a: Lanes<N>, b: Lanes<N>, f: impl Fn(f32, f32) -> f32) -> Lanes<N> {
    core::array::from_fn(|l| f(a[l], b[l]))
}

/// The multipliers `(ca s, cb s)` of `N` elements from their end-to-end vectors `e` and
/// relative displacements `r`, per axis.
///
/// Written step by step over all `N` elements, not element by element: with the compressed
/// spring's selects in it, the compiler vectorised the element-by-element form across the
/// wrong values, and the spring pass cost 40 to 60 % more (`examples/stress.rs`, 64 x 64).
#[inline(always)]
fn several<const N: usize, const SOFT: bool>(
    e: [Lanes<N>; 3],
    r: [Lanes<N>; 3],
    data: &RunData,
    k: usize,
) -> (Lanes<N>, Lanes<N>) {
    let (rest, ca, cb) = (
        load::<N>(data.rest, k),
        load::<N>(data.ca, k),
        load::<N>(data.cb, k),
    );
    let mut squared = [0.0; N];
    let mut dot = [0.0; N];
    for l in 0..N {
        squared[l] = e[0][l] * e[0][l] + e[1][l] * e[1][l] + e[2][l] * e[2][l];
        dot[l] = e[0][l] * r[0][l] + e[1][l] * r[1][l] + e[2][l] * r[2][l];
    }
    let mut s = [0.0; N];
    if !SOFT {
        // As stiff in compression as in tension: what the lines below give with `r = 1`, to
        // the bit (their denominator is then exactly 1).
        for l in 0..N {
            let length = squared[l].sqrt();
            let inverse = 1.0 / length.max(1e-9);
            let violation = length - rest[l];
            s[l] = -(violation + data.gamma * (dot[l] * inverse)) * inverse;
        }
        return (zip(ca, s, |c, s| c * s), zip(cb, s, |c, s| c * s));
    }
    let give = 1.0 - data.compression;
    // One division for both `1 / |e|` and the compressed spring's `1 / (|e| (1 − (1 − r)
    // (ca + cb)))` (see the module's notes).
    let mut length = [0.0; N];
    let mut inverse = [0.0; N];
    let mut inverse_softer = [0.0; N];
    for l in 0..N {
        length[l] = squared[l].sqrt();
        let denominator = (1.0 - give * (ca[l] + cb[l])).max(1e-6);
        inverse_softer[l] = 1.0 / (length[l].max(1e-9) * denominator);
        inverse[l] = inverse_softer[l] * denominator;
    }
    for l in 0..N {
        let violation = length[l] - rest[l];
        let compressed = violation < 0.0;
        let scale = if compressed { data.compression } else { 1.0 };
        let last = if compressed {
            inverse_softer[l]
        } else {
            inverse[l]
        };
        s[l] = -(scale * violation + data.gamma * (dot[l] * inverse[l])) * last;
    }
    (zip(ca, s, |c, s| c * s), zip(cb, s, |c, s| c * s))
}

/// A lane whose two ends lie in separate arrays: element `k` joins `(xa, ua)[k]` to
/// `(xb, ub)[k]`. Four elements at a time, eight where the CPU has AVX (the same operations
/// on each element, so the same result to the bit).
pub(crate) fn project_split(
    x: ([&[f32]; 3], [&[f32]; 3]),
    ua: &mut [&mut [f32]; 3],
    ub: &mut [&mut [f32]; 3],
    data: RunData,
) {
    let soft = is_soft(&data);
    #[cfg(target_arch = "x86_64")]
    if wide::available() {
        return wide::project_split(x, ua, ub, data, soft);
    }
    if soft {
        split_lane::<4, true>(x, ua, ub, data);
    } else {
        split_lane::<4, false>(x, ua, ub, data);
    }
}

/// [`project_split`], `N` elements at a time.
#[inline(always)]
fn split_lane<const N: usize, const SOFT: bool>(
    (xa, xb): ([&[f32]; 3], [&[f32]; 3]),
    ua: &mut [&mut [f32]; 3],
    ub: &mut [&mut [f32]; 3],
    data: RunData,
) {
    let len = data.rest.len();
    // The per-element arrays cut to one length too, so one test covers a chunk's reads.
    let data = data.cut(len);
    let x = (xa.map(|s| &s[..len]), xb.map(|s| &s[..len]));
    let [ua0, ua1, ua2] = ua;
    let [ub0, ub1, ub2] = ub;
    let mut ua = [&mut ua0[..len], &mut ua1[..len], &mut ua2[..len]];
    let mut ub = [&mut ub0[..len], &mut ub1[..len], &mut ub2[..len]];
    let chunks = len / N;
    for chunk in 0..chunks {
        split_chunk::<N, SOFT>(x, (&mut ua, &mut ub), &data, N * chunk);
    }
    for k in N * chunks..len {
        split_chunk::<1, SOFT>(x, (&mut ua, &mut ub), &data, k);
    }
}

/// The `N` elements from `k` of a lane whose ends lie in separate arrays.
#[inline(always)]
fn split_chunk<const N: usize, const SOFT: bool>(
    (xa, xb): ([&[f32]; 3], [&[f32]; 3]),
    (ua, ub): (&mut [&mut [f32]; 3], &mut [&mut [f32]; 3]),
    data: &RunData,
    k: usize,
) {
    let (moved_a, moved_b) = chunk_step::<N, SOFT>(
        load_axes(&xa, k),
        load_axes(&xb, k),
        load_axes(ua, k),
        load_axes(ub, k),
        (data, k),
    );
    store_axes(ua, k, moved_a);
    store_axes(ub, k, moved_b);
}

/// A lane whose two ends lie in the same arrays: element `k` joins index `a + k` to index
/// `b + k`. Four elements at a time when the ends are at least four apart (no two of the four
/// touch the same particle), eight when they are at least eight apart and the CPU has AVX,
/// otherwise one at a time; in order either way, so the result is the same to the bit.
pub(crate) fn project_shared(
    x: [&[f32]; 3],
    u: &mut [&mut [f32]; 3],
    a: usize,
    b: usize,
    data: RunData,
) {
    let soft = is_soft(&data);
    #[cfg(target_arch = "x86_64")]
    if a.abs_diff(b) >= 8 && wide::available() {
        return wide::project_shared(x, u, a, b, data, soft);
    }
    if soft {
        shared_lane::<4, true>(x, u, a, b, data);
    } else {
        shared_lane::<4, false>(x, u, a, b, data);
    }
}

/// Lanes whose ends lie in the same arrays, each on arrays of its own (a grid's quarter
/// grids), with the same ends `a` and `b` and the same length: what [`project_shared`] does
/// on each in turn, to the bit, with their chunks taken in turn instead. In one such lane a
/// chunk whose ends are less than two chunks apart waits for the one before it to be stored
/// (on a 32-wide grid every chunk of a south lane does); chunks of separate lanes do not
/// wait on one another, so the processor works on `L` of them at once.
pub(crate) fn project_shared_together<const L: usize>(
    x: [[&[f32]; 3]; L],
    u: &mut [[&mut [f32]; 3]; L],
    (a, b): (usize, usize),
    data: [RunData; L],
) {
    let soft = data.iter().any(is_soft);
    #[cfg(target_arch = "x86_64")]
    if a.abs_diff(b) >= 8 && wide::available() {
        return wide::project_shared_together(x, u, (a, b), data, soft);
    }
    if soft {
        shared_lanes::<4, L, true>(x, u, (a, b), data);
    } else {
        shared_lanes::<4, L, false>(x, u, (a, b), data);
    }
}

/// [`project_shared`], `N` elements at a time when the ends are at least `N` apart. (The
/// same as [`shared_lanes`] with one lane, but a loop of its own: through that one the
/// compiler's code took 5 % more instructions.)
#[inline(always)]
fn shared_lane<const N: usize, const SOFT: bool>(
    x: [&[f32]; 3],
    u: &mut [&mut [f32]; 3],
    a: usize,
    b: usize,
    data: RunData,
) {
    let len = data.rest.len();
    let data = data.cut(len);
    let end = a.max(b) + len;
    // Every array cut to one length, so one test covers a chunk's reads.
    let x = x.map(|s| &s[..end]);
    let [u0, u1, u2] = u;
    let mut u = [&mut u0[..end], &mut u1[..end], &mut u2[..end]];
    let chunks = if a.abs_diff(b) >= N { len / N } else { 0 };
    for chunk in 0..chunks {
        let k = N * chunk;
        shared_chunk::<N, SOFT>(x, &mut u, (a + k, b + k), &data, k);
    }
    for k in N * chunks..len {
        shared_chunk::<1, SOFT>(x, &mut u, (a + k, b + k), &data, k);
    }
}

/// [`project_shared_together`], `N` elements at a time when the ends are at least `N` apart:
/// every lane's first chunk, then every lane's second, and so on, then each lane's last
/// elements one at a time.
#[inline(always)]
fn shared_lanes<const N: usize, const L: usize, const SOFT: bool>(
    x: [[&[f32]; 3]; L],
    u: &mut [[&mut [f32]; 3]; L],
    (a, b): (usize, usize),
    data: [RunData; L],
) {
    let len = data[0].rest.len();
    let data = data.map(|data| data.cut(len));
    let end = a.max(b) + len;
    let x = x.map(|x| x.map(|s| &s[..end]));
    let mut u = u
        .each_mut()
        .map(|[u0, u1, u2]| [&mut u0[..end], &mut u1[..end], &mut u2[..end]]);
    let chunks = if a.abs_diff(b) >= N { len / N } else { 0 };
    for chunk in 0..chunks {
        let k = N * chunk;
        for lane in 0..L {
            shared_chunk::<N, SOFT>(x[lane], &mut u[lane], (a + k, b + k), &data[lane], k);
        }
    }
    for lane in 0..L {
        for k in N * chunks..len {
            shared_chunk::<1, SOFT>(x[lane], &mut u[lane], (a + k, b + k), &data[lane], k);
        }
    }
}

/// The `N` elements from `k` of a lane whose ends lie in the same arrays, ends at `ia` and
/// `ib` (at least `N` apart).
#[inline(always)]
fn shared_chunk<const N: usize, const SOFT: bool>(
    x: [&[f32]; 3],
    u: &mut [&mut [f32]; 3],
    (ia, ib): (usize, usize),
    data: &RunData,
    k: usize,
) {
    let (moved_a, moved_b) = chunk_step::<N, SOFT>(
        load_axes(&x, ia),
        load_axes(&x, ib),
        load_axes(u, ia),
        load_axes(u, ib),
        (data, k),
    );
    store_axes(u, ia, moved_a);
    store_axes(u, ib, moved_b);
}

/// One chunk of `N` elements (the `N` from `k` of `data`): from its ends' positions at the
/// start of the substep, `xa` and `xb`, and their motions so far, `pa` and `pb` (per axis),
/// the motions after the projection.
#[inline(always)]
fn chunk_step<const N: usize, const SOFT: bool>(
    xa: [Lanes<N>; 3],
    xb: [Lanes<N>; 3],
    pa: [Lanes<N>; 3],
    pb: [Lanes<N>; 3],
    (data, k): (&RunData, usize),
) -> ([Lanes<N>; 3], [Lanes<N>; 3]) {
    // Written out axis by axis: through `array::from_fn` the compiler kept the lanes apart
    // and the kernels took three times the instructions.
    let r = [
        zip(pa[0], pb[0], |p, q| p - q),
        zip(pa[1], pb[1], |p, q| p - q),
        zip(pa[2], pb[2], |p, q| p - q),
    ];
    let e = [
        zip(zip(xa[0], xb[0], |p, q| p - q), r[0], |p, q| p + q),
        zip(zip(xa[1], xb[1], |p, q| p - q), r[1], |p, q| p + q),
        zip(zip(xa[2], xb[2], |p, q| p - q), r[2], |p, q| p + q),
    ];
    let (sa, sb) = several::<N, SOFT>(e, r, data, k);
    (
        [
            zip(pa[0], zip(sa, e[0], |p, q| p * q), |p, q| p + q),
            zip(pa[1], zip(sa, e[1], |p, q| p * q), |p, q| p + q),
            zip(pa[2], zip(sa, e[2], |p, q| p * q), |p, q| p + q),
        ],
        [
            zip(pb[0], zip(sb, e[0], |p, q| p * q), |p, q| p - q),
            zip(pb[1], zip(sb, e[1], |p, q| p * q), |p, q| p - q),
            zip(pb[2], zip(sb, e[2], |p, q| p * q), |p, q| p - q),
        ],
    )
}

/// The lane kernels eight elements at a time, compiled for AVX and used where the CPU has it
/// (checked at run time, once). Only AVX: no fused multiply-add, which would round
/// differently from the four-wide loops and make results depend on the CPU.
#[cfg(target_arch = "x86_64")]
#[allow(unsafe_code)]
mod wide {
    use super::{RunData, shared_lane, shared_lanes, split_lane};

    pub(super) use crate::sim::simd::avx_available as available;

    /// [`super::project_split`] eight elements at a time, the softer compression's form when
    /// `soft`. Only called when [`available`].
    pub(super) fn project_split(
        x: ([&[f32]; 3], [&[f32]; 3]),
        ua: &mut [&mut [f32]; 3],
        ub: &mut [&mut [f32]; 3],
        data: RunData,
        soft: bool,
    ) {
        // SAFETY: called only after `available()` found AVX on this CPU.
        unsafe {
            if soft {
                split_avx::<true>(x, ua, ub, data)
            } else {
                split_avx::<false>(x, ua, ub, data)
            }
        }
    }

    /// [`super::project_shared`] eight elements at a time, for ends at least eight apart.
    /// Only called when [`available`].
    pub(super) fn project_shared(
        x: [&[f32]; 3],
        u: &mut [&mut [f32]; 3],
        a: usize,
        b: usize,
        data: RunData,
        soft: bool,
    ) {
        // SAFETY: called only after `available()` found AVX on this CPU.
        unsafe {
            if soft {
                shared_avx::<true>(x, u, a, b, data)
            } else {
                shared_avx::<false>(x, u, a, b, data)
            }
        }
    }

    /// [`super::project_shared_together`] eight elements at a time, for ends at least eight
    /// apart. Only called when [`available`].
    pub(super) fn project_shared_together<const L: usize>(
        x: [[&[f32]; 3]; L],
        u: &mut [[&mut [f32]; 3]; L],
        ends: (usize, usize),
        data: [RunData; L],
        soft: bool,
    ) {
        // SAFETY: called only after `available()` found AVX on this CPU.
        unsafe {
            if soft {
                shared_together_avx::<L, true>(x, u, ends, data)
            } else {
                shared_together_avx::<L, false>(x, u, ends, data)
            }
        }
    }

    #[target_feature(enable = "avx")]
    fn shared_together_avx<const L: usize, const SOFT: bool>(
        x: [[&[f32]; 3]; L],
        u: &mut [[&mut [f32]; 3]; L],
        ends: (usize, usize),
        data: [RunData; L],
    ) {
        shared_lanes::<8, L, SOFT>(x, u, ends, data);
    }

    #[target_feature(enable = "avx")]
    fn split_avx<const SOFT: bool>(
        x: ([&[f32]; 3], [&[f32]; 3]),
        ua: &mut [&mut [f32]; 3],
        ub: &mut [&mut [f32]; 3],
        data: RunData,
    ) {
        split_lane::<8, SOFT>(x, ua, ub, data);
    }

    #[target_feature(enable = "avx")]
    fn shared_avx<const SOFT: bool>(
        x: [&[f32]; 3],
        u: &mut [&mut [f32]; 3],
        a: usize,
        b: usize,
        data: RunData,
    ) {
        shared_lane::<8, SOFT>(x, u, a, b, data);
    }
}

/// Springs with arbitrary ends (`a[k]`, `b[k]`), one after another: meshes.
pub(crate) fn project_indexed(arrays: &mut Arrays, a: &[u32], b: &[u32], data: RunData) {
    let n = data.rest.len();
    let (a, b) = (&a[..n], &b[..n]);
    let data = data.cut(n);
    for k in 0..n {
        let (ia, ib) = (a[k] as usize, b[k] as usize);
        // One element, as a lane's last ones: `a` is moved, then `b`, each from what it was.
        let (moved_a, moved_b) = chunk_step::<1, true>(
            load_axes(&arrays.x, ia),
            load_axes(&arrays.x, ib),
            load_axes(&arrays.u, ia),
            load_axes(&arrays.u, ib),
            (&data, k),
        );
        store_axes(&mut arrays.u, ia, moved_a);
        store_axes(&mut arrays.u, ib, moved_b);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The textbook projection of one spring, written out with vectors: compliance `alpha`
    /// and damping factor `gamma` when stretched, `alpha / r` and `gamma / r` when compressed
    /// (stiffness `r k`, the same damping coefficient).
    fn reference(
        pa: glam::Vec3,
        pb: glam::Vec3,
        moved: glam::Vec3,
        rest: f32,
        (wa, wb, alpha, gamma, r): (f32, f32, f32, f32, f32),
    ) -> (glam::Vec3, glam::Vec3) {
        let delta = pa - pb;
        let n = delta.normalize();
        let c = delta.length() - rest;
        let (alpha, gamma) = if c < 0.0 {
            (alpha / r, gamma / r)
        } else {
            (alpha, gamma)
        };
        let dl = (-c - gamma * n.dot(moved)) / ((1.0 + gamma) * (wa + wb) + alpha);
        (wa * dl * n, -wb * dl * n)
    }

    #[test]
    fn a_spring_with_no_push_and_no_damping_moves_nothing_when_compressed_however_stiff() {
        // `ca + cb` is 1: infinitely stiff, undamped; compression fraction 0. Spring 0 is
        // compressed, spring 1 stretched.
        let x: [Vec<f32>; 3] = [vec![0.0, 0.8, 0.9, 2.2], vec![0.0; 4], vec![0.0; 4]];
        let mut u: [Vec<f32>; 3] = [vec![0.0; 4], vec![0.0; 4], vec![0.0; 4]];
        let (rest, ca, cb) = ([1.0f32, 1.0], [0.5f32, 0.5], [0.5f32, 0.5]);
        let data = RunData {
            rest: &rest,
            ca: &ca,
            cb: &cb,
            gamma: 0.0,
            compression: 0.0,
        };
        let [u0, u1, u2] = &mut u;
        let mut arrays = Arrays {
            x: [&x[0], &x[1], &x[2]],
            u: [u0, u1, u2],
        };
        project_indexed(&mut arrays, &[0, 2], &[1, 3], data);
        assert_eq!(
            u[0][..2],
            [0.0, 0.0],
            "the compressed spring pushes with nothing"
        );
        // The stretched one (1.3 m, rest 1 m) is pulled back to its length, half each way.
        assert!(
            (u[0][2] - 0.15).abs() < 1e-6 && (u[0][3] + 0.15).abs() < 1e-6,
            "{u:?}"
        );
    }

    #[test]
    fn every_loop_shape_matches_the_textbook_projection() {
        // Six particles in a row, each already moved a little this substep (`u`); springs
        // (0,3), (1,4), (2,5) over disjoint stretches, both ways round, and through indices.
        // The last is compressed, and a fifth as stiff so.
        let xs = [0.0f32, 0.11, 0.19, 0.33, 0.38, 0.52];
        let x: [Vec<f32>; 3] = [
            xs.to_vec(),
            vec![0.0, 0.01, -0.02, 0.0, 0.03, 0.0],
            vec![0.0; 6],
        ];
        let u0: [Vec<f32>; 3] = [
            vec![0.001, -0.002, 0.0, 0.003, 0.0, -0.001],
            vec![0.0; 6],
            vec![0.0005; 6],
        ];
        let (wa, wb, alpha, gamma, r) = (2.0f32, 0.5f32, 0.3f32, 0.2f32, 0.2f32);
        let den = (1.0 + gamma) * (wa + wb) + alpha;
        let rest = [0.3f32, 0.25, 0.35];
        let (ca, cb) = ([wa / den; 3], [wb / den; 3]);
        let data = RunData {
            rest: &rest,
            ca: &ca,
            cb: &cb,
            gamma,
            compression: r,
        };
        let at = |a: &[Vec<f32>; 3], i: usize| glam::Vec3::new(a[0][i], a[1][i], a[2][i]);
        let check = |u: &[Vec<f32>; 3], pairs: [(usize, usize); 3]| {
            for (k, (a, b)) in pairs.into_iter().enumerate() {
                let moved = at(&u0, a) - at(&u0, b);
                let (pa, pb) = (at(&x, a) + at(&u0, a), at(&x, b) + at(&u0, b));
                let (da, db) = reference(pa, pb, moved, rest[k], (wa, wb, alpha, gamma, r));
                assert_eq!(
                    k == 2,
                    (pa - pb).length() < rest[k],
                    "the last alone compressed"
                );
                let (ua, ub) = (at(u, a) - at(&u0, a), at(u, b) - at(&u0, b));
                assert!((ua - da).length() < 1e-6, "{pairs:?} {k}: {ua} vs {da}");
                assert!((ub - db).length() < 1e-6, "{pairs:?} {k}: {ub} vs {db}");
            }
        };
        let run = |f: &dyn Fn(&mut Arrays)| {
            let mut u = u0.clone();
            let [u_x, u_y, u_z] = &mut u;
            f(&mut Arrays {
                x: [&x[0], &x[1], &x[2]],
                u: [u_x, u_y, u_z],
            });
            u
        };
        check(
            &run(&|a| project_shared(a.x, &mut a.u, 0, 3, data)),
            [(0, 3), (1, 4), (2, 5)],
        );
        check(
            &run(&|arrays| {
                let [x0, x1, x2] = arrays.x;
                let [u0, u1, u2] = &mut arrays.u;
                let (u0a, u0b) = u0.split_at_mut(3);
                let (u1a, u1b) = u1.split_at_mut(3);
                let (u2a, u2b) = u2.split_at_mut(3);
                project_split(
                    (
                        [&x0[3..], &x1[3..], &x2[3..]],
                        [&x0[..3], &x1[..3], &x2[..3]],
                    ),
                    &mut [u0b, u1b, u2b],
                    &mut [u0a, u1a, u2a],
                    data,
                )
            }),
            [(3, 0), (4, 1), (5, 2)],
        );
        check(
            &run(&|a| project_indexed(a, &[5, 0, 2], &[1, 3, 4], data)),
            [(5, 1), (0, 3), (2, 4)],
        );
    }

    #[test]
    fn a_lane_four_at_a_time_matches_the_same_springs_one_by_one() {
        // A chain of 40 particles; lanes join each to the one `gap` further on. With a gap of
        // at least 4 the lane goes four elements at a time (eight with AVX and a gap of at
        // least 8), each reading what the elements before it wrote; with a smaller gap it
        // goes one at a time. Every way must equal the springs projected one by one in order.
        let n = 40;
        let x: [Vec<f32>; 3] = [
            (0..n)
                .map(|i| 0.1 * i as f32 + 0.003 * (i % 3) as f32)
                .collect(),
            (0..n).map(|i| 0.01 * (i % 5) as f32).collect(),
            vec![0.0; n],
        ];
        let u0: [Vec<f32>; 3] = [
            (0..n).map(|i| 1e-3 * (i % 4) as f32).collect(),
            vec![-2e-4; n],
            (0..n).map(|i| 5e-4 * (i % 2) as f32).collect(),
        ];
        for gap in [1usize, 3, 4, 5, 8, 9, 16] {
            let len = n - gap;
            let rest: Vec<f32> = (0..len)
                .map(|k| 0.09 * gap as f32 + 0.001 * k as f32)
                .collect();
            let (ca, cb) = (vec![0.4f32; len], vec![0.3f32; len]);
            let data = RunData {
                rest: &rest,
                ca: &ca,
                cb: &cb,
                gamma: 0.15,
                compression: 1.0,
            };
            let run = |f: &dyn Fn(&mut Arrays)| {
                let mut u = u0.clone();
                let [u_x, u_y, u_z] = &mut u;
                f(&mut Arrays {
                    x: [&x[0], &x[1], &x[2]],
                    u: [u_x, u_y, u_z],
                });
                u
            };
            let a: Vec<u32> = (0..len as u32).collect();
            let b: Vec<u32> = (gap as u32..n as u32).collect();
            let one_by_one = run(&|arrays| project_indexed(arrays, &a, &b, data));
            let lane = run(&|arrays| project_shared(arrays.x, &mut arrays.u, 0, gap, data));
            assert_eq!(lane, one_by_one, "gap {gap}");
        }
    }

    #[test]
    fn lanes_side_by_side_equal_each_lane_in_turn_to_the_bit() {
        // Four chains of 60 particles, each with its own positions, motion and springs, as a
        // grid's four quarter grids have; a lane in each joins a particle to the one `gap` on.
        let n = 60;
        let value = |i: usize, scale: f32| scale * ((i * 7919 % 101) as f32 - 50.0) / 37.0;
        let x: [[Vec<f32>; 3]; 4] = core::array::from_fn(|q| {
            core::array::from_fn(|axis| {
                (0..n)
                    .map(|i| {
                        0.04 * (axis == 1) as u8 as f32 * i as f32 + value(i + 13 * q + axis, 1e-3)
                    })
                    .collect()
            })
        });
        let u0: [[Vec<f32>; 3]; 4] = core::array::from_fn(|q| {
            core::array::from_fn(|axis| (0..n).map(|i| value(i + 7 * q + axis, 1e-5)).collect())
        });
        // Four lanes side by side below 16 slots, two from 16 (as the solver takes them).
        for gap in [3usize, 5, 8, 9, 12, 15, 16, 21, 31] {
            let len = n - gap;
            let per_lane = |q: usize, scale: f32, base: f32| -> Vec<f32> {
                (0..len).map(|k| base + value(k + 3 * q, scale)).collect()
            };
            let rest: [Vec<f32>; 4] =
                core::array::from_fn(|q| per_lane(q, 1e-3, 0.04 * gap as f32));
            let ca: [Vec<f32>; 4] = core::array::from_fn(|q| per_lane(q + 1, 1e-2, 0.3));
            let cb: [Vec<f32>; 4] = core::array::from_fn(|q| per_lane(q + 2, 1e-2, 0.2));
            let data: [RunData; 4] = core::array::from_fn(|q| RunData {
                rest: &rest[q],
                ca: &ca[q],
                cb: &cb[q],
                gamma: 0.05 * q as f32,
                compression: 0.3,
            });
            let xs: [[&[f32]; 3]; 4] = core::array::from_fn(|q| x[q].each_ref().map(|a| &a[..]));
            let mut in_turn = u0.clone();
            for (q, u) in in_turn.iter_mut().enumerate() {
                let [u_x, u_y, u_z] = u;
                project_shared(xs[q], &mut [u_x, u_y, u_z], 0, gap, data[q]);
            }
            let mut together = u0.clone();
            let mut u = together
                .each_mut()
                .map(|[u_x, u_y, u_z]| [&mut u_x[..], &mut u_y[..], &mut u_z[..]]);
            if gap < 16 {
                project_shared_together(xs, &mut u, (0, gap), data);
            } else {
                let [u01, u23] = {
                    let [a, b, c, d] = u;
                    [[a, b], [c, d]]
                };
                let (mut u01, mut u23) = (u01, u23);
                project_shared_together([xs[0], xs[1]], &mut u01, (0, gap), [data[0], data[1]]);
                project_shared_together([xs[2], xs[3]], &mut u23, (0, gap), [data[2], data[3]]);
            }
            let bits = |u: &[[Vec<f32>; 3]; 4]| {
                u.iter()
                    .flatten()
                    .flatten()
                    .map(|v| v.to_bits())
                    .collect::<Vec<_>>()
            };
            assert_ne!(
                bits(&in_turn),
                bits(&u0),
                "gap {gap}: the springs moved nothing"
            );
            assert_eq!(bits(&together), bits(&in_turn), "gap {gap}");
        }
    }

    /// Lanes of 37 elements (four chunks of eight and a tail of five) on 80 particles, values
    /// spread over several orders of magnitude so any difference in rounding would show:
    /// `check` gets the motions a reference projection and a tested one leave, for a shared
    /// lane at several gaps and for a split lane.
    fn compare_lanes(
        compression: f32,
        reference: (SharedFn, SplitFn),
        tested: (SharedFn, SplitFn),
        check: impl Fn([Vec<u32>; 3], [Vec<u32>; 3], &str),
    ) {
        let n = 80;
        let value = |i: usize, scale: f32| scale * ((i * 7919 % 101) as f32 - 50.0) / 37.0;
        let x: [Vec<f32>; 3] = [
            (0..n).map(|i| 0.05 * i as f32 + value(i, 1e-3)).collect(),
            (0..n).map(|i| value(i + 3, 1e-2)).collect(),
            (0..n).map(|i| value(i + 5, 1e-4)).collect(),
        ];
        let u0: [Vec<f32>; 3] =
            core::array::from_fn(|axis| (0..n).map(|i| value(i + axis, 1e-5)).collect());
        let len = 37;
        // Rest lengths within 10 % of the springs' lengths (0.05 m a slot apart), so some are
        // stretched and some compressed.
        let rest_for = |gap: usize| -> Vec<f32> {
            (0..len)
                .map(|k| 0.05 * gap as f32 * (1.0 + value(k, 0.07)))
                .collect()
        };
        let ca: Vec<f32> = (0..len).map(|k| 0.3 + value(k + 1, 1e-2)).collect();
        let cb: Vec<f32> = (0..len).map(|k| 0.2 + value(k + 2, 1e-2)).collect();
        let run = |f: &dyn Fn([&[f32]; 3], &mut [&mut [f32]; 3])| {
            let mut u = u0.clone();
            let [u_x, u_y, u_z] = &mut u;
            f([&x[0], &x[1], &x[2]], &mut [u_x, u_y, u_z]);
            u
        };
        let bits = |u: [Vec<f32>; 3]| u.map(|a| a.iter().map(|v| v.to_bits()).collect::<Vec<_>>());
        for gap in [8, 11, 27] {
            let rest = rest_for(gap);
            let data = test_data(&rest, &ca, &cb, compression);
            let expected = run(&|x, u| reference.0(x, u, gap, data));
            let got = run(&|x, u| tested.0(x, u, gap, data));
            check(
                bits(expected),
                bits(got),
                &format!("shared lane, gap {gap}"),
            );
        }
        let rest = rest_for(n / 2);
        let data = test_data(&rest, &ca, &cb, compression);
        let split = |f: SplitFn| {
            run(&|x, u| {
                let [u0, u1, u2] = u;
                let (u0a, u0b) = u0.split_at_mut(n / 2);
                let (u1a, u1b) = u1.split_at_mut(n / 2);
                let (u2a, u2b) = u2.split_at_mut(n / 2);
                let ends = (x, x.map(|axis| &axis[n / 2..]));
                f(ends, &mut [u0a, u1a, u2a], &mut [u0b, u1b, u2b], data);
            })
        };
        check(
            bits(split(reference.1)),
            bits(split(tested.1)),
            "split lane",
        );
    }

    /// A run's data with the damping factor `compare_lanes` uses.
    fn test_data<'a>(
        rest: &'a [f32],
        ca: &'a [f32],
        cb: &'a [f32],
        compression: f32,
    ) -> RunData<'a> {
        RunData {
            rest,
            ca,
            cb,
            gamma: 0.07,
            compression,
        }
    }

    type SharedFn = fn([&[f32]; 3], &mut [&mut [f32]; 3], usize, RunData);
    type SplitFn =
        fn(([&[f32]; 3], [&[f32]; 3]), &mut [&mut [f32]; 3], &mut [&mut [f32]; 3], RunData);

    /// The softer compression's form, four elements at a time, on any CPU.
    const SOFT_FOUR: (SharedFn, SplitFn) = (
        |x, u, gap, data| shared_lane::<4, true>(x, u, 0, gap, data),
        |x, ua, ub, data| split_lane::<4, true>(x, ua, ub, data),
    );

    /// The plain form, four elements at a time, on any CPU.
    const PLAIN_FOUR: (SharedFn, SplitFn) = (
        |x, u, gap, data| shared_lane::<4, false>(x, u, 0, gap, data),
        |x, ua, ub, data| split_lane::<4, false>(x, ua, ub, data),
    );

    #[test]
    fn springs_as_stiff_in_compression_take_the_plain_form_with_the_same_bits() {
        compare_lanes(1.0, SOFT_FOUR, PLAIN_FOUR, |expected, got, lane| {
            assert_eq!(expected, got, "{lane}");
        });
        // And the softer form is not the plain one when the springs do give.
        compare_lanes(0.3, SOFT_FOUR, PLAIN_FOUR, |expected, got, lane| {
            assert_ne!(expected, got, "{lane}: no spring was compressed");
        });
    }

    #[test]
    #[cfg(target_arch = "x86_64")]
    fn eight_wide_lanes_equal_four_wide_to_the_bit() {
        if !wide::available() {
            eprintln!("no AVX on this CPU: the eight-wide loops are not used");
            return;
        }
        // The dispatching entry points, so with `r = 1` the plain eight-wide form is checked
        // against the general four-wide one.
        let eight: (SharedFn, SplitFn) = (
            |x, u, gap, data| project_shared(x, u, 0, gap, data),
            |x, ua, ub, data| project_split(x, ua, ub, data),
        );
        for compression in [0.3, 1.0] {
            compare_lanes(compression, SOFT_FOUR, eight, |expected, got, lane| {
                assert_eq!(expected, got, "{lane}, compression {compression}");
            });
        }
    }
}
