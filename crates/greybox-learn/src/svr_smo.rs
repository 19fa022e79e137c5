//! libsvm's SMO for the ε-SVR dual (Chang & Lin, ACM TIST 2011, sections 4.1 and 5): WSS3
//! working-set selection (Fan, Chen & Lin, JMLR 6, 2005), shrinking (Joachims 1999; libsvm's
//! rule), and kernel rows computed on demand into a bounded least-recently-used cache instead
//! of the whole kernel matrix, so memory is O(l) plus the cache.
//!
//! The iterates are those of the full-matrix solver this replaces, bit for bit: every kernel
//! value is computed by the same expression, the gradient updates and the reconstruction of
//! the shrunk variables' gradients add the same terms in the same order (see the test
//! against the full-matrix reference, `tests/common/old_svr.rs`).

use crate::svr_rows::{kernel_diagonal, kernel_row};
use greybox_model::svr::SvrParams;
use greybox_model::Matrix;

const TAU: f64 = 1e-12;

/// The solution of the dual in the original variable order (t < l: α_t; t ≥ l: α*_{t−l}),
/// with the gradient of every variable and the SMO iterations used.
pub struct Dual {
    pub alpha: Vec<f64>,
    pub grad: Vec<f64>,
    pub iterations: usize,
}

/// Solve the ε-SVR dual on standardised rows `z` with at most `cache_bytes` of cached kernel
/// rows (at least two rows are kept whatever the budget).
pub fn solve(p: &SvrParams, z: &Matrix, y: &[f64], gamma: f64, cache_bytes: usize) -> Dual {
    let l = z.n_rows;
    let fill = |r: usize, row: &mut [f64]| kernel_row(p, gamma, z, r, row);
    let qd = kernel_diagonal(p, gamma, z);
    let cache = KernelCache::new(l, cache_bytes, fill);
    let max_iter = p.max_iter.unwrap_or((100 * l).max(10_000_000));
    let mut smo = Smo::new(cache, &qd, p.c, p.tol, p.epsilon, y);
    let iterations = smo.solve(max_iter);
    let n2 = 2 * l;
    let mut alpha = vec![0.0; n2];
    let mut grad = vec![0.0; n2];
    for t in 0..n2 {
        alpha[smo.orig[t]] = smo.alpha[t];
        grad[smo.orig[t]] = smo.grad[t];
    }
    Dual {
        alpha,
        grad,
        iterations,
    }
}

/// Kernel rows K(r, ·) in the original column order, computed on demand and kept while the
/// memory budget allows; the least recently used row is recomputed over when it does not.
struct KernelCache<F> {
    fill: F,
    l: usize,
    max_slots: usize,
    /// Slot s holds the row of `owner[s]` at `data[s l .. (s+1) l]`.
    data: Vec<f64>,
    owner: Vec<usize>,
    /// Last use of each slot (a counter of loads).
    stamp: Vec<u64>,
    /// The slot of each kernel row, `NONE` when not cached.
    slot_of: Vec<usize>,
    clock: u64,
}

const NONE: usize = usize::MAX;

/// A quiet NaN's bits: OR-ed into a value, a NaN, which no `>=` selects.
const NAN_BITS: u64 = 0x7ff8_0000_0000_0000;

/// Independent running maxima in the argmax scans (variable t goes to lane t mod LANES).
const LANES: usize = 4;

/// The (value, t) of the lanes' maxima with the largest value, the largest t among equal
/// values: what one sequential scan keeping the last maximum (`v >= best`) finds, since
/// `>=` on values that are never NaN is a total order. `None` when no lane saw a candidate.
#[inline]
fn merge_lanes(best: &[(f64, usize); LANES]) -> Option<(f64, usize)> {
    let mut out: Option<(f64, usize)> = None;
    for &(v, t) in best {
        if t == NONE {
            continue;
        }
        if out.is_none_or(|(w, u)| v > w || (v == w && t > u)) {
            out = Some((v, t));
        }
    }
    out
}

impl<F: Fn(usize, &mut [f64])> KernelCache<F> {
    fn new(l: usize, bytes: usize, fill: F) -> Self {
        let max_slots = (bytes / (8 * l.max(1))).max(2).min(l.max(1));
        KernelCache {
            fill,
            l,
            max_slots,
            // address space only: pages are touched as slots fill
            data: Vec::with_capacity(max_slots * l),
            owner: Vec::with_capacity(max_slots),
            stamp: Vec::with_capacity(max_slots),
            slot_of: vec![NONE; l],
            clock: 0,
        }
    }

    /// The slot holding row r, computing it if needed. A load never evicts the row of the
    /// previous load (at least two slots), so two rows can be held at once.
    fn load(&mut self, r: usize) -> usize {
        self.clock += 1;
        let s = self.slot_of[r];
        if s != NONE {
            self.stamp[s] = self.clock;
            return s;
        }
        let l = self.l;
        let s = if self.owner.len() < self.max_slots {
            self.owner.push(r);
            self.stamp.push(self.clock);
            self.data.resize(self.data.len() + l, 0.0);
            self.owner.len() - 1
        } else {
            let (s, _) = self
                .stamp
                .iter()
                .enumerate()
                .min_by_key(|&(_, &t)| t)
                .expect("at least one slot");
            self.slot_of[self.owner[s]] = NONE;
            self.owner[s] = r;
            self.stamp[s] = self.clock;
            s
        };
        self.slot_of[r] = s;
        (self.fill)(r, &mut self.data[s * l..(s + 1) * l]);
        s
    }

    #[inline]
    fn slot(&self, s: usize) -> &[f64] {
        &self.data[s * self.l..(s + 1) * self.l]
    }
}

/// The working-order columns the WSS3 j scan reads (all of the active length).
struct JCols<'a> {
    ys: &'a [f64],
    grad: &'a [f64],
    low: &'a [bool],
    qd: &'a [f64],
    kit: &'a [f64],
}

/// The WSS3 j scan: G_max2 = max over I_low of y_t G_t, and the (b²/a, t) of the largest
/// b²/a over t ∈ I_low with b = G_max + y_t G_t > 0 (the last t on ties). With AVX2 where
/// the processor has it: the same operations on the same values, so the same bits.
fn scan_j(gmax: f64, qdi: f64, c: &JCols) -> (f64, Option<(f64, usize)>) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the processor has AVX2 (checked above)
        return unsafe { scan_j_avx2(gmax, qdi, c) };
    }
    scan_j_lanes(gmax, qdi, c)
}

/// The lanes' running (key, t) maxima of an AVX2 scan: lane k keeps the last t ≡ k (mod 4)
/// with the largest key, as the scalar scan's lane k does (a NaN key is never taken).
#[cfg(target_arch = "x86_64")]
struct ArgMax {
    key: std::arch::x86_64::__m256d,
    idx: std::arch::x86_64::__m256i,
    /// The positions t of the four values offered next.
    tv: std::arch::x86_64::__m256i,
}

#[cfg(target_arch = "x86_64")]
impl ArgMax {
    #[target_feature(enable = "avx2")]
    fn new() -> Self {
        use std::arch::x86_64::*;
        ArgMax {
            key: _mm256_set1_pd(f64::NEG_INFINITY),
            idx: _mm256_set1_epi64x(-1),
            tv: _mm256_set_epi64x(3, 2, 1, 0),
        }
    }

    /// Offers the next four values (positions `tv`), keeping each lane's last maximum.
    #[target_feature(enable = "avx2")]
    fn take(&mut self, v: std::arch::x86_64::__m256d) {
        use std::arch::x86_64::*;
        let take = _mm256_cmp_pd::<_CMP_GE_OQ>(v, self.key);
        self.key = _mm256_blendv_pd(self.key, v, take);
        self.idx = _mm256_castpd_si256(_mm256_blendv_pd(
            _mm256_castsi256_pd(self.idx),
            _mm256_castsi256_pd(self.tv),
            take,
        ));
        self.tv = _mm256_add_epi64(self.tv, _mm256_set1_epi64x(LANES as i64));
    }

    /// Each lane's (key, t), `NONE` where nothing was taken.
    #[target_feature(enable = "avx2")]
    fn lanes(&self) -> [(f64, usize); LANES] {
        use std::arch::x86_64::*;
        let mut keys = [0.0; LANES];
        let mut ids = [0i64; LANES];
        // SAFETY: LANES = 4 elements each
        unsafe {
            _mm256_storeu_pd(keys.as_mut_ptr(), self.key);
            _mm256_storeu_si256(ids.as_mut_ptr().cast(), self.idx);
        }
        std::array::from_fn(|k| (keys[k], if ids[k] < 0 { NONE } else { ids[k] as usize }))
    }
}

/// All-ones lanes where `flags[k]` is set (the four flags from `flags[0]`).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn lane_mask(flags: &[bool]) -> std::arch::x86_64::__m256d {
    use std::arch::x86_64::*;
    let bytes = u32::from_le_bytes(std::array::from_fn(|k| flags[k] as u8));
    _mm256_castsi256_pd(_mm256_sub_epi64(
        _mm256_setzero_si256(),
        _mm256_cvtepu8_epi64(_mm_cvtsi32_si128(bytes as i32)),
    ))
}

/// [`scan_j_lanes`] four t at a time in AVX2 registers (lane k of a register is lane k of
/// the scalar scan): the same IEEE operations in the same order on the same values, so the
/// same G_max2 and the same (b²/a, t), bit for bit.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn scan_j_avx2(gmax: f64, qdi: f64, c: &JCols) -> (f64, Option<(f64, usize)>) {
    use std::arch::x86_64::*;
    let n = c.ys.len();
    let (ys, grad, low, qd, kit) = (c.ys, &c.grad[..n], &c.low[..n], &c.qd[..n], &c.kit[..n]);
    let whole = n - n % LANES;
    let (gv, qdiv) = (_mm256_set1_pd(gmax), _mm256_set1_pd(qdi));
    let (two, tau, zero) = (
        _mm256_set1_pd(2.0),
        _mm256_set1_pd(TAU),
        _mm256_setzero_pd(),
    );
    let nan = _mm256_set1_pd(f64::NAN);
    let mut gmax2 = _mm256_set1_pd(f64::NEG_INFINITY);
    let mut best = ArgMax::new();
    for base in (0..whole).step_by(LANES) {
        // SAFETY: base + 3 < whole ≤ n, the length of every column
        let (v, qdt, k) = unsafe {
            let y = _mm256_loadu_pd(ys.as_ptr().add(base));
            let g = _mm256_loadu_pd(grad.as_ptr().add(base));
            let q = _mm256_loadu_pd(qd.as_ptr().add(base));
            let k = _mm256_loadu_pd(kit.as_ptr().add(base));
            (_mm256_mul_pd(y, g), q, k)
        };
        let in_low = lane_mask(&low[base..]);
        let b = _mm256_add_pd(gv, v);
        let vl = _mm256_blendv_pd(_mm256_set1_pd(f64::NEG_INFINITY), v, in_low);
        gmax2 = _mm256_max_pd(vl, gmax2); // vl > gmax2 ? vl : gmax2
        let quad = _mm256_sub_pd(_mm256_add_pd(qdiv, qdt), _mm256_mul_pd(two, k));
        let a = _mm256_blendv_pd(tau, quad, _mm256_cmp_pd::<_CMP_GT_OQ>(quad, zero));
        let obj = _mm256_div_pd(_mm256_mul_pd(b, b), a);
        let cand = _mm256_and_pd(in_low, _mm256_cmp_pd::<_CMP_GT_OQ>(b, zero));
        best.take(_mm256_blendv_pd(nan, obj, cand));
    }
    let mut g2 = [0.0; LANES];
    // SAFETY: LANES = 4 elements
    unsafe { _mm256_storeu_pd(g2.as_mut_ptr(), gmax2) };
    let best = best.lanes();
    let mut lanes = Lanes {
        gmax2: g2,
        key: best.map(|b| b.0),
        idx: best.map(|b| b.1),
    };
    for t in whole..n {
        lanes.visit(gmax, qdi, c, t, t % LANES);
    }
    lanes.finish()
}

/// [`scan_j`] with [`LANES`] independent maxima (t in lane t mod LANES) merged at the end.
fn scan_j_lanes(gmax: f64, qdi: f64, c: &JCols) -> (f64, Option<(f64, usize)>) {
    let mut lanes = Lanes {
        gmax2: [f64::NEG_INFINITY; LANES],
        key: [f64::NEG_INFINITY; LANES],
        idx: [NONE; LANES],
    };
    for t in 0..c.ys.len() {
        lanes.visit(gmax, qdi, c, t, t % LANES);
    }
    lanes.finish()
}

/// The running maxima of the j scan, one per lane.
struct Lanes {
    gmax2: [f64; LANES],
    key: [f64; LANES],
    idx: [usize; LANES],
}

impl Lanes {
    /// Branch-free (masks, not ifs, which the compiler would turn back into jumps): a t
    /// outside I_low counts as −∞ in G_max2, and a t outside the candidates gets a NaN
    /// objective, which is never ≥ anything.
    #[inline(always)]
    fn visit(&mut self, gmax: f64, qdi: f64, c: &JCols, t: usize, lane: usize) {
        let v = c.ys[t] * c.grad[t];
        let b = gmax + v;
        let out = (!c.low[t]) as u64;
        let keep = out.wrapping_sub(1); // all ones in I_low
        let neg_inf = f64::NEG_INFINITY.to_bits();
        let vl = f64::from_bits((v.to_bits() & keep) | (neg_inf & !keep));
        let g2 = &mut self.gmax2[lane];
        *g2 = if vl > *g2 { vl } else { *g2 };
        // Q_ii + Q_tt − 2 y_i y_t Q_it = K_ii + K_tt − 2 K_it
        let quad = qdi + c.qd[t] - 2.0 * c.kit[t];
        let a = if quad > 0.0 { quad } else { TAU };
        let skip = (out | (b <= 0.0) as u64).wrapping_neg() & NAN_BITS;
        let obj = f64::from_bits((b * b / a).to_bits() | skip);
        if obj >= self.key[lane] {
            self.key[lane] = obj;
            self.idx[lane] = t;
        }
    }

    fn finish(&self) -> (f64, Option<(f64, usize)>) {
        let best = std::array::from_fn(|k| (self.key[k], self.idx[k]));
        let g = self.gmax2.iter().fold(f64::NEG_INFINITY, |m, &v| m.max(v));
        (g, merge_lanes(&best))
    }
}

/// The working-order columns of the gradient update (all of the active length).
struct GCols<'a> {
    grad: &'a mut [f64],
    ys: &'a [f64],
    up: &'a [bool],
    kit: &'a [f64],
    kr: &'a [usize],
}

/// G_t += y_t (K_it Δ_i + K_jt Δ_j) over the active set (`kj`: K_j in original order), and
/// the next i candidate: the (−y_t G_t, t) of its largest value over I_up, the last t on
/// ties. With AVX2 where the processor has it: the same operations, the same bits.
fn update_grad(c: &mut GCols, kj: &[f64], di: f64, dj: f64) -> Option<(f64, usize)> {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the processor has AVX2 (checked above)
        return unsafe { update_grad_avx2(c, kj, di, dj) };
    }
    let mut best = [(f64::NEG_INFINITY, NONE); LANES];
    update_grad_from(c, kj, di, dj, 0, &mut best);
    merge_lanes(&best)
}

/// [`update_grad`] from t = `start` on, one t at a time into the lanes' maxima.
#[inline(always)]
fn update_grad_from(
    c: &mut GCols,
    kj: &[f64],
    di: f64,
    dj: f64,
    start: usize,
    best: &mut [(f64, usize); LANES],
) {
    for t in start..c.grad.len() {
        let (g, yt) = (&mut c.grad[t], c.ys[t]);
        *g += yt * (c.kit[t] * di + kj[c.kr[t]] * dj);
        if c.up[t] {
            let v = -yt * *g;
            let lane = t % LANES;
            if v >= best[lane].0 {
                best[lane] = (v, t);
            }
        }
    }
}

/// [`update_grad`] four t at a time in AVX2 registers (lane k = the scalar lane k): the same
/// IEEE operations in the same order on the same values.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn update_grad_avx2(c: &mut GCols, kj: &[f64], di: f64, dj: f64) -> Option<(f64, usize)> {
    use std::arch::x86_64::*;
    let n = c.grad.len();
    assert!(c.ys.len() == n && c.up.len() == n && c.kit.len() == n && c.kr.len() == n);
    let whole = n - n % LANES;
    let (dv, djv) = (_mm256_set1_pd(di), _mm256_set1_pd(dj));
    let (nan, sign) = (_mm256_set1_pd(f64::NAN), _mm256_set1_pd(-0.0));
    let mut next_i = ArgMax::new();
    for base in (0..whole).step_by(LANES) {
        // K_jt by scalar loads (checked indices; faster than a gather instruction here)
        let kjt: [f64; LANES] = std::array::from_fn(|k| kj[c.kr[base + k]]);
        // SAFETY: base + 3 < whole ≤ n, the length of every column
        let (y, g) = unsafe {
            let y = _mm256_loadu_pd(c.ys.as_ptr().add(base));
            let g = _mm256_loadu_pd(c.grad.as_ptr().add(base));
            let k = _mm256_loadu_pd(c.kit.as_ptr().add(base));
            let kjt = _mm256_loadu_pd(kjt.as_ptr());
            let term = _mm256_add_pd(_mm256_mul_pd(k, dv), _mm256_mul_pd(kjt, djv));
            (y, _mm256_add_pd(g, _mm256_mul_pd(y, term)))
        };
        // SAFETY: as above
        unsafe { _mm256_storeu_pd(c.grad.as_mut_ptr().add(base), g) };
        let in_up = lane_mask(&c.up[base..]);
        let v = _mm256_mul_pd(_mm256_xor_pd(y, sign), g); // −y_t G_t
        next_i.take(_mm256_blendv_pd(nan, v, in_up));
    }
    let mut best = next_i.lanes();
    update_grad_from(c, kj, di, dj, whole, &mut best);
    merge_lanes(&best)
}

/// The factor ±y_t C by which Ḡ changes along K_t· when α_t moves from `old` to `new`:
/// + when it reached the upper bound C, − when it left it, `None` otherwise.
#[inline]
pub fn g_bar_change(old: f64, new: f64, c: f64, yt: f64) -> Option<f64> {
    match (old >= c, new >= c) {
        (false, true) => Some(yt * c),
        (true, false) => Some(-(yt * c)),
        _ => None,
    }
}

/// libsvm's SMO solver for the ε-SVR dual over 2l variables (variable t < l is α_t with
/// y_t = +1, t ≥ l is α*_{t−l} with y_t = −1; Q_st = y_s y_t K(s mod l, t mod l)).
/// Variables are kept in working order: the active (unshrunk) ones first, as in libsvm, so
/// every loop runs over a prefix; `kr[t]` is the kernel row of the variable at position t.
struct Smo<F> {
    cache: KernelCache<F>,
    l: usize,
    c: f64,
    tol: f64,
    alpha: Vec<f64>,
    grad: Vec<f64>,
    ys: Vec<f64>,
    kr: Vec<usize>,
    qd: Vec<f64>,
    lin: Vec<f64>,
    orig: Vec<usize>,
    /// t ∈ I_up (α_t can move up along y_t) and t ∈ I_low, kept in step with α.
    up: Vec<bool>,
    low: Vec<bool>,
    active: usize,
    /// Scratch: the kernel row of the working-set i in working order.
    kit: Vec<f64>,
    /// libsvm's Ḡ: Σ over the variables s at the upper bound of y_s K_ts C, for every t
    /// (shrunk or not), kept up to date whenever a variable reaches or leaves C, so that
    /// rebuilding the shrunk gradients only walks the free variables (Chang & Lin 2011, §4.1).
    g_bar: Vec<f64>,
}

impl<F: Fn(usize, &mut [f64])> Smo<F> {
    fn new(cache: KernelCache<F>, diag: &[f64], c: f64, tol: f64, epsilon: f64, y: &[f64]) -> Self {
        let l = diag.len();
        let n2 = 2 * l;
        let kr: Vec<usize> = (0..n2).map(|t| t % l).collect();
        let lin: Vec<f64> = (0..n2)
            .map(|t| {
                if t < l {
                    epsilon - y[t]
                } else {
                    epsilon + y[t - l]
                }
            })
            .collect();
        Smo {
            cache,
            l,
            c,
            tol,
            alpha: vec![0.0; n2],
            grad: lin.clone(),
            ys: (0..n2).map(|t| if t < l { 1.0 } else { -1.0 }).collect(),
            qd: kr.iter().map(|&r| diag[r]).collect(),
            kr,
            lin,
            orig: (0..n2).collect(),
            up: vec![false; n2],
            low: vec![false; n2],
            active: n2,
            kit: vec![0.0; n2],
            g_bar: vec![0.0; n2],
        }
        .with_flags()
    }

    fn with_flags(mut self) -> Self {
        for t in 0..self.alpha.len() {
            self.set_flags(t);
        }
        self
    }

    #[inline]
    fn set_flags(&mut self, t: usize) {
        let (a, c) = (self.alpha[t], self.c);
        let pos = self.ys[t] > 0.0;
        self.up[t] = if pos { a < c } else { a > 0.0 };
        self.low[t] = if pos { a > 0.0 } else { a < c };
    }

    fn swap(&mut self, a: usize, b: usize) {
        self.alpha.swap(a, b);
        self.grad.swap(a, b);
        self.ys.swap(a, b);
        self.kr.swap(a, b);
        self.qd.swap(a, b);
        self.lin.swap(a, b);
        self.orig.swap(a, b);
        self.up.swap(a, b);
        self.low.swap(a, b);
        self.g_bar.swap(a, b);
    }

    /// Recompute the gradients of the shrunk variables, G_t = p_t + y_t (Ḡ_t + Σ_s y_s K_ts
    /// α_s) over the free α_s (0 < α_s < C), one kernel row each (the sums run over s in
    /// working order).
    fn reconstruct(&mut self) {
        let (n2, act) = (self.alpha.len(), self.active);
        if act == n2 {
            return;
        }
        let mut acc = self.g_bar[act..].to_vec();
        for s in 0..n2 {
            let a = self.alpha[s];
            if a == 0.0 || a >= self.c {
                continue;
            }
            let ys = self.ys[s];
            let slot = self.cache.load(self.kr[s]);
            let row = self.cache.slot(slot);
            for (g, &r) in acc.iter_mut().zip(&self.kr[act..]) {
                *g += ys * row[r] * a;
            }
        }
        for (t, g) in (act..n2).zip(acc) {
            self.grad[t] = self.lin[t] + self.ys[t] * g;
        }
        self.active = n2;
    }

    /// libsvm's shrinking: set aside bound variables that cannot enter the working set; once
    /// the violation is within 10 tol, unshrink everything (once) and go on from there.
    fn shrink(&mut self, unshrunk: &mut bool) {
        let (mut g1, mut g2) = (f64::NEG_INFINITY, f64::NEG_INFINITY);
        for t in 0..self.active {
            if self.up[t] {
                g1 = g1.max(-self.ys[t] * self.grad[t]);
            }
            if self.low[t] {
                g2 = g2.max(self.ys[t] * self.grad[t]);
            }
        }
        if !*unshrunk && g1 + g2 <= self.tol * 10.0 {
            *unshrunk = true;
            self.reconstruct();
        }
        let be_shrunk = |s: &Self, t: usize| {
            let (a, yt, gt) = (s.alpha[t], s.ys[t], s.grad[t]);
            if a >= s.c {
                if yt > 0.0 {
                    -gt > g1
                } else {
                    -gt > g2
                }
            } else if a <= 0.0 {
                if yt > 0.0 {
                    gt > g2
                } else {
                    gt > g1
                }
            } else {
                false
            }
        };
        let mut t = 0;
        while t < self.active {
            if be_shrunk(self, t) {
                self.active -= 1;
                while self.active > t {
                    if !be_shrunk(self, self.active) {
                        self.swap(t, self.active);
                        break;
                    }
                    self.active -= 1;
                }
            }
            t += 1;
        }
    }

    /// The i of WSS3: argmax over I_up of −y_t G_t.
    fn select_i(&self) -> Option<(f64, usize)> {
        let mut best = [(f64::NEG_INFINITY, NONE); LANES];
        for t in 0..self.active {
            if self.up[t] {
                let v = -self.ys[t] * self.grad[t];
                let lane = t % LANES;
                if v >= best[lane].0 {
                    best[lane] = (v, t);
                }
            }
        }
        merge_lanes(&best)
    }

    /// The j of WSS3 (Fan, Chen & Lin 2005) for a given i; `None` at convergence: the
    /// argmax over I_low with b = G_max + y_t G_t > 0 of b²/a (libsvm's −b²/a minimised),
    /// the last such t on ties. The scan keeps [`LANES`] independent maxima (t in lane
    /// t mod LANES) merged at the end, which is the same argmax with no loop-carried chain.
    fn select_j(&mut self, gmax: f64, i: usize) -> Option<usize> {
        let slot = self.cache.load(self.kr[i]);
        let act = self.active;
        // K_it in working order, so that the scan reads every array contiguously
        let ki = self.cache.slot(slot);
        for (k, &r) in self.kit[..act].iter_mut().zip(&self.kr[..act]) {
            *k = ki[r];
        }
        let cols = JCols {
            ys: &self.ys[..act],
            grad: &self.grad[..act],
            low: &self.low[..act],
            qd: &self.qd[..act],
            kit: &self.kit[..act],
        };
        let (gmax2, j) = scan_j(gmax, self.qd[i], &cols);
        if gmax + gmax2 < self.tol {
            None
        } else {
            j.map(|(_, t)| t)
        }
    }

    /// The new (α_i, α_j) of the two-variable subproblem (libsvm `Solver::Solve`).
    fn step(&self, i: usize, j: usize, kij: f64) -> (f64, f64) {
        let c = self.c;
        let quad = self.qd[i] + self.qd[j] - 2.0 * kij;
        let quad = if quad > 0.0 { quad } else { TAU };
        let (mut ai, mut aj) = (self.alpha[i], self.alpha[j]);
        if self.ys[i] != self.ys[j] {
            let delta = (-self.grad[i] - self.grad[j]) / quad;
            let diff = ai - aj;
            ai += delta;
            aj += delta;
            if diff > 0.0 {
                if aj < 0.0 {
                    aj = 0.0;
                    ai = diff;
                }
            } else if ai < 0.0 {
                ai = 0.0;
                aj = -diff;
            }
            if diff > 0.0 {
                if ai > c {
                    ai = c;
                    aj = c - diff;
                }
            } else if aj > c {
                aj = c;
                ai = c + diff;
            }
        } else {
            let delta = (self.grad[i] - self.grad[j]) / quad;
            let sum = ai + aj;
            ai -= delta;
            aj += delta;
            if sum > c {
                if ai > c {
                    ai = c;
                    aj = sum - c;
                }
            } else if aj < 0.0 {
                aj = 0.0;
                ai = sum;
            }
            if sum > c {
                if aj > c {
                    aj = c;
                    ai = sum - c;
                }
            } else if ai < 0.0 {
                ai = 0.0;
                aj = sum;
            }
        }
        (ai, aj)
    }

    /// Two-variable update, then the gradient of the active set. Returns the next i
    /// candidate, found in the same pass.
    fn update(&mut self, i: usize, j: usize) -> Option<(f64, usize)> {
        let si = self.cache.load(self.kr[i]);
        let sj = self.cache.load(self.kr[j]);
        let kij = self.cache.slot(si)[self.kr[j]];
        let (old_i, old_j) = (self.alpha[i], self.alpha[j]);
        let (ai, aj) = self.step(i, j, kij);
        self.alpha[i] = ai;
        self.alpha[j] = aj;
        self.set_flags(i);
        self.set_flags(j);
        for (t, old, slot) in [(i, old_i, si), (j, old_j, sj)] {
            if let Some(term) = g_bar_change(old, self.alpha[t], self.c, self.ys[t]) {
                let row = self.cache.slot(slot);
                for (g, &r) in self.g_bar.iter_mut().zip(&self.kr) {
                    *g += term * row[r];
                }
            }
        }
        let (di, dj) = ((ai - old_i) * self.ys[i], (aj - old_j) * self.ys[j]);
        let act = self.active;
        // K_i in working order is `kit`, gathered by `select_j` for this i and this active set
        let mut cols = GCols {
            grad: &mut self.grad[..act],
            ys: &self.ys[..act],
            up: &self.up[..act],
            kit: &self.kit[..act],
            kr: &self.kr[..act],
        };
        update_grad(&mut cols, self.cache.slot(sj), di, dj)
    }

    /// Run SMO until the maximal violation is below `tol`; returns the iterations used.
    fn solve(&mut self, max_iter: usize) -> usize {
        let n2 = self.alpha.len();
        let mut unshrunk = false;
        let period = self.l.min(1000);
        let mut counter = period;
        let mut next_i = self.select_i();
        let mut iter = 0;
        while iter < max_iter {
            counter -= 1;
            if counter == 0 {
                counter = period;
                self.shrink(&mut unshrunk);
                next_i = self.select_i();
            }
            let mut pair = next_i.and_then(|(g, i)| self.select_j(g, i).map(|j| (i, j)));
            if pair.is_none() && self.active < n2 {
                self.reconstruct();
                next_i = self.select_i();
                pair = next_i.and_then(|(g, i)| self.select_j(g, i).map(|j| (i, j)));
                counter = 1;
            }
            let Some((i, j)) = pair else { break };
            iter += 1;
            next_i = self.update(i, j);
        }
        if self.active < n2 {
            self.reconstruct();
        }
        iter
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// The AVX2 scans give the portable scans' bits: the same G_max2, j, next i and
    /// gradients, on random columns of every length modulo 4 (ties included).
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn avx2_scans_equal_the_portable_scans_bit_for_bit() {
        if !std::arch::is_x86_feature_detected!("avx2") {
            return;
        }
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        for n in [0, 1, 2, 3, 4, 5, 7, 8, 13, 64, 301] {
            let l = n.max(1);
            // values on a coarse grid, so that ties occur
            let mut draw = |k: f64| (rng.gen_range(-4.0f64..4.0) * k).round() / k;
            let ys: Vec<f64> = (0..n)
                .map(|t| if t % 3 == 0 { -1.0 } else { 1.0 })
                .collect();
            let grad: Vec<f64> = (0..n).map(|_| draw(4.0)).collect();
            let qd: Vec<f64> = (0..n).map(|_| 1.0 + draw(2.0).abs() / 8.0).collect();
            let kit: Vec<f64> = (0..n).map(|_| draw(8.0) / 4.0).collect();
            let kr: Vec<usize> = (0..n).map(|t| (t * 7) % l).collect();
            let kj: Vec<f64> = (0..l).map(|_| draw(8.0) / 4.0).collect();
            let low: Vec<bool> = (0..n).map(|t| t % 5 != 1).collect();
            let up: Vec<bool> = (0..n).map(|t| t % 4 != 2).collect();
            let cols = JCols {
                ys: &ys,
                grad: &grad,
                low: &low,
                qd: &qd,
                kit: &kit,
            };
            for gmax in [-1.0, 0.0, 0.5, 2.0] {
                let a = scan_j_lanes(gmax, 1.0, &cols);
                // SAFETY: AVX2 checked above
                let b = unsafe { scan_j_avx2(gmax, 1.0, &cols) };
                assert_eq!(a.0.to_bits(), b.0.to_bits(), "n {n}");
                assert_eq!(
                    a.1.map(|(v, t)| (v.to_bits(), t)),
                    b.1.map(|(v, t)| (v.to_bits(), t))
                );
            }
            let (mut g1, mut g2) = (grad.clone(), grad.clone());
            let mut best = [(f64::NEG_INFINITY, NONE); LANES];
            let mut c1 = GCols {
                grad: &mut g1,
                ys: &ys,
                up: &up,
                kit: &kit,
                kr: &kr,
            };
            update_grad_from(&mut c1, &kj, 0.25, -0.5, 0, &mut best);
            let a = merge_lanes(&best);
            let mut c2 = GCols {
                grad: &mut g2,
                ys: &ys,
                up: &up,
                kit: &kit,
                kr: &kr,
            };
            // SAFETY: AVX2 checked above
            let b = unsafe { update_grad_avx2(&mut c2, &kj, 0.25, -0.5) };
            assert_eq!(
                a.map(|(v, t)| (v.to_bits(), t)),
                b.map(|(v, t)| (v.to_bits(), t))
            );
            assert!(g1.iter().zip(&g2).all(|(x, y)| x.to_bits() == y.to_bits()));
        }
    }

    /// The cache keeps at most its budget's rows, evicts the least recently used one, and
    /// gives every row as computed.
    #[test]
    fn kernel_cache_evicts_the_least_recently_used_row() {
        let computed = std::cell::RefCell::new(Vec::new());
        let fill = |r: usize, row: &mut [f64]| {
            computed.borrow_mut().push(r);
            for (s, v) in row.iter_mut().enumerate() {
                *v = (10 * r + s) as f64;
            }
        };
        let mut cache = KernelCache::new(5, 3 * 8 * 5, fill);
        for r in [0, 1, 2, 0, 3, 1, 0, 4] {
            let s = cache.load(r);
            assert_eq!(cache.slot(s)[4], (10 * r + 4) as f64);
        }
        // 3 evicts 1 (0 was used after it), 1 evicts 2, 4 evicts 3
        assert_eq!(*computed.borrow(), vec![0, 1, 2, 3, 1, 4]);
        assert_eq!(cache.owner.len(), 3);
    }
}

#[cfg(test)]
mod bench {
    use super::*;
    use greybox_model::matrix::Standardizer;

    /// Dev timing: SVR_BENCH_CSV=rows.csv cargo test --release -p greybox-learn bench_ -- --ignored --nocapture
    #[test]
    #[ignore]
    fn bench_solve_on_csv() {
        let Ok(path) = std::env::var("SVR_BENCH_CSV") else {
            return;
        };
        let text = std::fs::read_to_string(path).unwrap();
        let mut rows = Vec::new();
        let mut y = Vec::new();
        for line in text.lines().skip(1) {
            let f: Vec<f64> = line.split(',').map(|s| s.parse().unwrap()).collect();
            rows.push(vec![f[0], f[1]]);
            y.push(f[2]);
        }
        let p = SvrParams {
            kernel: greybox_model::svr::Kernel::Rbf,
            c: 10.0,
            epsilon: 0.01,
            ..Default::default()
        };
        for n in [rows.len() / 2, rows.len()] {
            let x = Matrix::from_rows(&rows[..n]);
            let z = Standardizer::fit(&x).transform(&x);
            let t0 = std::time::Instant::now();
            let d = solve(&p, &z, &y[..n], 0.5, 512 << 20);
            let nsv = (0..n).filter(|&r| d.alpha[r] != d.alpha[r + n]).count();
            eprintln!(
                "{n} rows: {:.3} s, {} iterations, {nsv} SV",
                t0.elapsed().as_secs_f64(),
                d.iterations
            );
        }
    }
}
