//! Cubic evaluation of a block of parameters that lies within a few knot spans (sorted
//! parameters on a curve with fewer knots than points, or clustered ones), with AVX-512:
//! the knots, the reciprocals of the Cox–de Boor recursion and the control points of the
//! block's spans fit in tables of 16 values, from which every lane takes its own with one
//! permutation (`vpermt2pd`) instead of a gather. The operations of
//! [`super::curve::basis_funs_cubic`] and of the accumulation in the other kernels, in the
//! same order and without fused multiply-adds: the same bits.

use super::locate::{Locator, BLOCK};

/// The most knots a block may cross: the knots k[s - 2..=s + 3] of its last span then
/// still lie in a table of 16 from k[s0 - 2] (s0: the block's first span).
const MAX_CROSSED: usize = 10;

/// The fewest parameters of a part of a block, each part with its own tables.
const MIN_PART: usize = 16;

/// The most blocks left to the other kernel after a failed try.
const MAX_WAIT: u32 = 63;

/// The narrow blocks' evaluation over a run of blocks: AVX-512 where the CPU has it
/// (checked once by `pulp`), the last span found, where the next search starts, and a
/// back-off: after a block that is not narrow, the next `wait` blocks go to the other
/// kernel without a try, `wait` doubling with each failure in a row (up to [`MAX_WAIT`]),
/// so that unsorted or dense parameters pay for a failed try only now and then.
pub(super) struct Narrow {
    #[cfg(target_arch = "x86_64")]
    v4: Option<pulp::x86::V4>,
    hint: usize,
    wait: u32,
    backoff: u32,
}

impl Narrow {
    pub(super) fn new(loc: &Locator) -> Self {
        Narrow {
            #[cfg(target_arch = "x86_64")]
            v4: pulp::x86::V4::try_new(),
            hint: loc.lo,
            wait: 0,
            backoff: 0,
        }
    }

    /// Evaluates the cubic with `control` (rows of D coordinates) on the knots of `loc`
    /// (not uniform) at the block's parameters `x` into `out` (rows of D), when the CPU has
    /// AVX-512 and the block, whole or in halves or quarters, crosses at most
    /// [`MAX_CROSSED`] knots; `false` otherwise (with some of `out` written: the caller's
    /// kernel then writes all of it, the same bits). Must be inlined into code compiled for
    /// AVX-512 ([`super::locate::with_avx512`]).
    #[inline(always)]
    pub(super) fn eval_cubic<const D: usize>(
        &mut self,
        loc: &Locator,
        control: &[f64],
        x: &[f64; BLOCK],
        out: &mut [f64],
    ) -> bool {
        #[cfg(target_arch = "x86_64")]
        if let Some(v4) = self.v4.filter(|_| loc.inv_step.is_none()) {
            if self.wait > 0 {
                self.wait -= 1;
                return false;
            }
            let (mut start, mut size) = (0, BLOCK);
            while start < BLOCK {
                let part = start..start + size;
                let o = &mut out[part.start * D..part.end * D];
                match x86::eval_part::<D>(v4, loc, control, &x[part], o, &mut self.hint) {
                    Ok(()) => {
                        start += size;
                        size = size.max(1 << start.trailing_zeros()).min(BLOCK);
                    }
                    // Split while the parts of MIN_PART could cross few enough knots.
                    Err(crossed) if size > MIN_PART && crossed * MIN_PART <= MAX_CROSSED * size => {
                        size /= 2;
                    }
                    Err(_) => {
                        self.backoff = (2 * self.backoff + 1).min(MAX_WAIT);
                        self.wait = self.backoff;
                        return false;
                    }
                }
            }
            self.backoff = 0;
            return true;
        }
        let _ = (loc, control, x, out);
        false
    }
}

#[cfg(target_arch = "x86_64")]
mod x86 {
    //! Every helper is `#[inline(always)]` and no intrinsic sits in a closure: a closure or
    //! a function that is not inlined is compiled without AVX-512, and its intrinsics
    //! become calls.
    use super::{Locator, MAX_CROSSED};
    use core::arch::x86_64::{__m512d, __m512i, _CMP_LE_OQ};
    use pulp::x86::V4;

    /// Eight doubles from the start of `a`.
    #[inline(always)]
    fn load(a: &[f64]) -> __m512d {
        let v: [f64; 8] = a[..8].try_into().expect("eight values");
        pulp::cast(v)
    }

    /// Eight doubles to the start of `a`.
    #[inline(always)]
    fn store(a: &mut [f64], v: __m512d) {
        a[..8].copy_from_slice(&pulp::cast::<__m512d, [f64; 8]>(v));
    }

    /// The operations of the kernel on vectors of eight lanes.
    #[derive(Clone, Copy)]
    struct Ops(V4);

    impl Ops {
        #[inline(always)]
        fn sub(self, a: __m512d, b: __m512d) -> __m512d {
            self.0.avx512f._mm512_sub_pd(a, b)
        }

        #[inline(always)]
        fn mul(self, a: __m512d, b: __m512d) -> __m512d {
            self.0.avx512f._mm512_mul_pd(a, b)
        }

        #[inline(always)]
        fn add(self, a: __m512d, b: __m512d) -> __m512d {
            self.0.avx512f._mm512_add_pd(a, b)
        }

        /// 1/(a - b).
        #[inline(always)]
        fn rec_diff(self, a: __m512d, b: __m512d) -> __m512d {
            let f = self.0.avx512f;
            f._mm512_div_pd(f._mm512_set1_pd(1.0), f._mm512_sub_pd(a, b))
        }

        #[inline(always)]
        fn splat(self, a: f64) -> __m512d {
            self.0.avx512f._mm512_set1_pd(a)
        }

        /// Whether a[i] <= a[i + 1] for i < 8.
        #[inline(always)]
        fn ascending(self, a: &[f64]) -> bool {
            let le = self
                .0
                .avx512f
                ._mm512_cmp_pd_mask::<_CMP_LE_OQ>(load(a), load(&a[1..]));
            le == 0xff
        }

        /// Lane i: idx[i] + r.
        #[inline(always)]
        fn plus(self, idx: __m512i, r: i64) -> __m512i {
            let f = self.0.avx512f;
            f._mm512_add_epi64(idx, f._mm512_set1_epi64(r))
        }

        /// Entry idx[i] of the table in lane i (indices below 16).
        #[inline(always)]
        fn take(self, table: Table, idx: __m512i) -> __m512d {
            self.0.avx512f._mm512_permutex2var_pd(table.0, idx, table.1)
        }

        /// Lane i: the lane's index, as `_mm512_set_epi64` in memory order.
        #[inline(always)]
        fn index(self, a: [i64; 8]) -> __m512i {
            self.0
                .avx512f
                ._mm512_set_epi64(a[7], a[6], a[5], a[4], a[3], a[2], a[1], a[0])
        }
    }

    /// Eight doubles from a[start..], the last one repeated past the end.
    #[inline(always)]
    fn load_clamped(a: &[f64], start: usize) -> __m512d {
        if start + 8 <= a.len() {
            return load(&a[start..]);
        }
        let v: [f64; 8] = std::array::from_fn(|i| a[(start + i).min(a.len() - 1)]);
        pulp::cast(v)
    }

    /// A table of 16 values as two vectors.
    #[derive(Clone, Copy)]
    struct Table(__m512d, __m512d);

    /// [`super::Narrow::eval_cubic`] on a part of a block (a multiple of 8 parameters,
    /// at least 16); when it crosses too many knots, their number, with nothing written.
    /// The spans are searched from `hint`, which is left at the last.
    #[inline(always)]
    pub(super) fn eval_part<const D: usize>(
        v4: V4,
        loc: &Locator,
        control: &[f64],
        x: &[f64],
        out: &mut [f64],
        hint: &mut usize,
    ) -> Result<(), usize> {
        let (f, op) = (v4.avx512f, Ops(v4));
        let n = x.len();
        // The spans of the least and the greatest parameter: every lane's span lies
        // between them, since spans grow with the parameter. Sorted (every lane against
        // the next), the first and the last: a branch, where the minimum and maximum are a
        // chain of dependent operations before the span lookups.
        let mut sorted = op.ascending(&x[n - 9..]);
        for g in 0..n / 8 - 1 {
            sorted &= op.ascending(&x[8 * g..]);
        }
        let (lo, hi) = if sorted {
            (x[0], x[n - 1])
        } else {
            let (mut lo, mut hi) = (load(x), load(x));
            for g in 1..n / 8 {
                let v = load(&x[8 * g..]);
                lo = f._mm512_min_pd(lo, v);
                hi = f._mm512_max_pd(hi, v);
            }
            (f._mm512_reduce_min_pd(lo), f._mm512_reduce_max_pd(hi))
        };
        let s0 = loc.span_from(lo, *hint);
        let s1 = loc.span_from(hi, s0);
        *hint = s1;
        let crossed = s1 - s0;
        if crossed > MAX_CROSSED {
            return Err(crossed);
        }
        let k = loc.knots;
        // The reciprocals of `cubic_span_inverses` on span s0 + r, for r <= crossed, from
        // the knots k[s0 + r + d], d = -2..=3.
        let at = |d: usize| load_clamped(k, s0 - 2 + d);
        let mut inv = [Table(f._mm512_setzero_pd(), f._mm512_setzero_pd()); 6];
        let pairs = [(3, 2), (3, 1), (4, 2), (3, 0), (4, 1), (5, 2)];
        for (q, (a, b)) in pairs.into_iter().enumerate() {
            inv[q].0 = op.rec_diff(at(a), at(b));
            if crossed >= 8 {
                inv[q].1 = op.rec_diff(at(a + 8), at(b + 8));
            }
        }
        // knots: k[s0 - 2 + r].
        let knots = Table(at(0), at(8));
        // The control rows s0 - 3 + r, coordinate by coordinate.
        let first = (s0 - 3) * D;
        let mut rows = [f._mm512_setzero_pd(); 6];
        for (i, v) in rows[..2 * D].iter_mut().enumerate() {
            *v = load_clamped(control, first + 8 * i);
        }
        let cwt = deinterleave::<D>(op, rows);
        // The knots k[s0 + 1..=s1].
        let next = &k[s0 + 1..=s1];
        for (g, o) in out.chunks_exact_mut(8 * D).enumerate() {
            let t = load(&x[8 * g..]);
            // The lane's span s0 + off: off counts the knots k[s0 + 1..=s1] at or below t.
            let mut off = f._mm512_setzero_si512();
            for &kj in next {
                let le = f._mm512_cmp_pd_mask::<_CMP_LE_OQ>(op.splat(kj), t);
                off = f._mm512_mask_sub_epi64(off, le, off, f._mm512_set1_epi64(-1));
            }
            // `basis_funs_cubic_with` on knots w[r] = k[s - 2 + r].
            let mut w = [t; 6];
            for (r, w) in w.iter_mut().enumerate() {
                *w = op.take(knots, op.plus(off, r as i64));
            }
            let [w0, w1, w2, w3, w4, w5] = w;
            let (l1, l2, l3) = (op.sub(t, w2), op.sub(t, w1), op.sub(t, w0));
            let (r1, r2, r3) = (op.sub(w3, t), op.sub(w4, t), op.sub(w5, t));
            let temp = op.take(inv[0], off);
            let (a0, a1) = (op.mul(r1, temp), op.mul(l1, temp));
            let temp = op.mul(a0, op.take(inv[1], off));
            let (b0, saved) = (op.mul(r1, temp), op.mul(l2, temp));
            let temp = op.mul(a1, op.take(inv[2], off));
            let (b1, b2) = (op.add(saved, op.mul(r2, temp)), op.mul(l1, temp));
            let temp = op.mul(b0, op.take(inv[3], off));
            let (c0, saved) = (op.mul(r1, temp), op.mul(l3, temp));
            let temp = op.mul(b1, op.take(inv[4], off));
            let (c1, saved) = (op.add(saved, op.mul(r2, temp)), op.mul(l2, temp));
            let temp = op.mul(b2, op.take(inv[5], off));
            let basis = [c0, c1, op.add(saved, op.mul(r3, temp)), op.mul(l1, temp)];
            // The sums from 0 over the four control rows s - 3..=s, as the other kernels.
            let mut p = [f._mm512_setzero_pd(); D];
            for (acc, table) in p.iter_mut().zip(&cwt) {
                for (j, b) in basis.iter().enumerate() {
                    let row = op.take(*table, op.plus(off, j as i64));
                    *acc = op.add(*acc, op.mul(*b, row));
                }
            }
            interleave::<D>(op, p, o);
        }
        Ok(())
    }

    /// Tables by coordinate of 16 rows of D coordinates (the first 2·D vectors of `rows`).
    #[inline(always)]
    fn deinterleave<const D: usize>(op: Ops, rows: [__m512d; 6]) -> [Table; D] {
        let f = op.0.avx512f;
        let mut t = [Table(rows[0], rows[1]); D];
        match D {
            1 => {}
            2 => {
                for (c, t) in t.iter_mut().enumerate() {
                    let idx = op.index(std::array::from_fn(|i| (2 * i + c) as i64));
                    t.0 = f._mm512_permutex2var_pd(rows[0], idx, rows[1]);
                    t.1 = f._mm512_permutex2var_pd(rows[2], idx, rows[3]);
                }
            }
            3 => {
                // Row i's coordinate c is element 3i + c of the three vectors: those of the
                // first two by one permutation, those of the third (3i + c >= 16) merged in.
                for (c, t) in t.iter_mut().enumerate() {
                    let e = |i: usize| (3 * i + c) as i64;
                    let two = op.index(std::array::from_fn(|i| e(i) & 15));
                    let third = op.index(std::array::from_fn(|i| e(i) & 7));
                    let late = (0..8).filter(|&i| e(i) >= 16).fold(0u8, |m, i| m | 1 << i);
                    let mut half = [rows[0]; 2];
                    for (h, v) in half.iter_mut().enumerate() {
                        let r = &rows[3 * h..];
                        let xy = f._mm512_permutex2var_pd(r[0], two, r[1]);
                        *v = f._mm512_mask_permutexvar_pd(xy, late, third, r[2]);
                    }
                    *t = Table(half[0], half[1]);
                }
            }
            _ => unreachable!("dimensions 1 to 3"),
        }
        t
    }

    /// Writes lanes of D coordinates as 8 rows of D.
    #[inline(always)]
    fn interleave<const D: usize>(op: Ops, p: [__m512d; D], o: &mut [f64]) {
        let f = op.0.avx512f;
        match D {
            1 => store(o, p[0]),
            2 => {
                let lo = op.index([0, 8, 1, 9, 2, 10, 3, 11]);
                store(o, f._mm512_permutex2var_pd(p[0], lo, p[1]));
                let hi = op.index([4, 12, 5, 13, 6, 14, 7, 15]);
                store(&mut o[8..], f._mm512_permutex2var_pd(p[0], hi, p[1]));
            }
            3 => {
                // x and y first, then z into the remaining places.
                let parts = [
                    (
                        [0, 8, 0, 1, 9, 0, 2, 10],
                        [0, 0, 0, 0, 0, 1, 0, 0],
                        0b0010_0100,
                    ),
                    (
                        [0, 3, 11, 0, 4, 12, 0, 5],
                        [2, 0, 0, 3, 0, 0, 4, 0],
                        0b0100_1001,
                    ),
                    (
                        [13, 0, 6, 14, 0, 7, 15, 0],
                        [0, 5, 0, 0, 6, 0, 0, 7],
                        0b1001_0010,
                    ),
                ];
                for (k, (xy, z, zmask)) in parts.into_iter().enumerate() {
                    let v = f._mm512_permutex2var_pd(p[0], op.index(xy), p[1]);
                    let v = f._mm512_mask_permutexvar_pd(v, zmask, op.index(z), p[2]);
                    store(&mut o[8 * k..], v);
                }
            }
            _ => {
                for (c, v) in p.iter().enumerate() {
                    let lanes = pulp::cast::<__m512d, [f64; 8]>(*v);
                    for (row, l) in o.chunks_exact_mut(D).zip(lanes) {
                        row[c] = l;
                    }
                }
            }
        }
    }
}
