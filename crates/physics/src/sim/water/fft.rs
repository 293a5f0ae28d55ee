//! A complex fast Fourier transform of power-of-two length, in one and two dimensions, for the
//! spectral near field (`spectral.rs`): the iterative radix-2 Cooley–Tukey algorithm (Cooley &
//! Tukey 1965; the in-place, bit-reversed form of Press et al., *Numerical Recipes*, §12.2).
//! Forward X_k = Σ_j x_j e^{−2πi jk/N}; the inverse has e^{+2πi jk/N} and the factor 1/N, so
//! inverse(forward(x)) = x to rounding. The twiddle factors are computed once per length with
//! `sin`/`cos` of each angle (not by recurrence), so the transform's error stays O(ε log N); the
//! order of every operation is fixed, so results are bit-identical run to run. No dependency: the
//! physics may use only glam, serde, thiserror and rayon.

/// A complex number (re, im) in f64.
pub type Complex = [f64; 2];

/// The plan of a transform of length `n` (a power of two ≥ 2): twiddles and the bit-reversal map.
#[derive(Debug, Clone)]
pub struct Fft {
    n: usize,
    /// e^{−2πi k/n}, k < n/2.
    twiddle: Vec<Complex>,
    /// The bit-reversed index of each position.
    reversed: Vec<usize>,
}

impl Fft {
    /// The plan for length `n`, or `None` unless `n` is a power of two ≥ 2.
    pub fn new(n: usize) -> Option<Self> {
        if n < 2 || !n.is_power_of_two() {
            return None;
        }
        let bits = n.trailing_zeros();
        let twiddle = (0..n / 2)
            .map(|k| {
                let a = -2.0 * std::f64::consts::PI * k as f64 / n as f64;
                [a.cos(), a.sin()]
            })
            .collect();
        let reversed = (0..n)
            .map(|i| i.reverse_bits() >> (usize::BITS - bits))
            .collect();
        Some(Self {
            n,
            twiddle,
            reversed,
        })
    }

    /// The length.
    pub fn len(&self) -> usize {
        self.n
    }

    /// Always false: a plan has length ≥ 2.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// Transforms `x` (length n) in place: forward, or inverse with the 1/n factor.
    pub fn transform(&self, x: &mut [Complex], inverse: bool) {
        debug_assert_eq!(x.len(), self.n);
        for (i, &r) in self.reversed.iter().enumerate() {
            if r > i {
                x.swap(i, r);
            }
        }
        let sign = if inverse { -1.0 } else { 1.0 };
        let mut half = 1;
        while half < self.n {
            let stride = self.n / (2 * half);
            for start in (0..self.n).step_by(2 * half) {
                for k in 0..half {
                    let [wr, wi] = self.twiddle[k * stride];
                    let wi = sign * wi;
                    let [br, bi] = x[start + k + half];
                    let t = [wr * br - wi * bi, wr * bi + wi * br];
                    let a = x[start + k];
                    x[start + k] = [a[0] + t[0], a[1] + t[1]];
                    x[start + k + half] = [a[0] - t[0], a[1] - t[1]];
                }
            }
            half *= 2;
        }
        if inverse {
            let s = 1.0 / self.n as f64;
            for v in x.iter_mut() {
                *v = [v[0] * s, v[1] * s];
            }
        }
    }

    /// Transforms an n × n array (row-major) in place: every row, then every column (through
    /// `scratch`, resized to n).
    pub fn transform_2d(&self, a: &mut [Complex], scratch: &mut Vec<Complex>, inverse: bool) {
        let n = self.n;
        debug_assert_eq!(a.len(), n * n);
        for row in a.chunks_exact_mut(n) {
            self.transform(row, inverse);
        }
        scratch.resize(n, [0.0; 2]);
        for c in 0..n {
            for (r, s) in scratch.iter_mut().enumerate() {
                *s = a[r * n + c];
            }
            self.transform(scratch, inverse);
            for (r, s) in scratch.iter().enumerate() {
                a[r * n + c] = *s;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dft(x: &[Complex], inverse: bool) -> Vec<Complex> {
        let n = x.len();
        let sign = if inverse { 1.0 } else { -1.0 };
        (0..n)
            .map(|k| {
                let mut s = [0.0; 2];
                for (j, v) in x.iter().enumerate() {
                    let a = sign * 2.0 * std::f64::consts::PI * ((j * k) % n) as f64 / n as f64;
                    let (c, si) = (a.cos(), a.sin());
                    s[0] += v[0] * c - v[1] * si;
                    s[1] += v[0] * si + v[1] * c;
                }
                if inverse {
                    [s[0] / n as f64, s[1] / n as f64]
                } else {
                    s
                }
            })
            .collect()
    }

    fn signal(n: usize, seed: u64) -> Vec<Complex> {
        let mut s = seed;
        let mut next = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((s >> 11) as f64 / (1u64 << 53) as f64) - 0.5
        };
        (0..n).map(|_| [next(), next()]).collect()
    }

    #[test]
    fn only_powers_of_two_have_a_plan() {
        assert!(Fft::new(0).is_none());
        assert!(Fft::new(1).is_none());
        assert!(Fft::new(12).is_none());
        assert_eq!(Fft::new(64).map(|f| f.len()), Some(64));
    }

    #[test]
    fn matches_the_direct_sum_both_ways() {
        for n in [2usize, 4, 8, 32, 128] {
            let x = signal(n, n as u64);
            let plan = Fft::new(n).unwrap();
            for inverse in [false, true] {
                let mut y = x.clone();
                plan.transform(&mut y, inverse);
                let want = dft(&x, inverse);
                // The direct sum's own rounding is O(n ε); the FFT's O(ε log n).
                let tol = 1e-13 * n as f64;
                for (a, b) in y.iter().zip(&want) {
                    assert!(
                        (a[0] - b[0]).abs() < tol && (a[1] - b[1]).abs() < tol,
                        "n {n}"
                    );
                }
            }
        }
    }

    #[test]
    fn the_inverse_undoes_the_forward_in_2d() {
        let n = 64;
        let plan = Fft::new(n).unwrap();
        let x = signal(n * n, 7);
        let mut y = x.clone();
        let mut scratch = Vec::new();
        plan.transform_2d(&mut y, &mut scratch, false);
        plan.transform_2d(&mut y, &mut scratch, true);
        let worst = x
            .iter()
            .zip(&y)
            .map(|(a, b)| (a[0] - b[0]).abs().max((a[1] - b[1]).abs()))
            .fold(0.0, f64::max);
        assert!(worst < 1e-14, "round trip error {worst}");
    }

    #[test]
    fn a_plane_wave_lands_on_its_one_mode_in_2d() {
        let n = 16;
        let plan = Fft::new(n).unwrap();
        let (kx, ky) = (3usize, 5usize);
        let mut a: Vec<Complex> = (0..n * n)
            .map(|i| {
                let (r, c) = (i / n, i % n);
                let ph = 2.0 * std::f64::consts::PI * ((kx * c + ky * r) as f64) / n as f64;
                [ph.cos(), ph.sin()]
            })
            .collect();
        plan.transform_2d(&mut a, &mut Vec::new(), false);
        for (i, v) in a.iter().enumerate() {
            let want = if i == ky * n + kx {
                (n * n) as f64
            } else {
                0.0
            };
            assert!(
                (v[0] - want).abs() < 1e-10 && v[1].abs() < 1e-10,
                "mode {i}: {v:?}"
            );
        }
    }
}
