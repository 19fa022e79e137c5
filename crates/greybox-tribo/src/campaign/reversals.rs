//! Where a recording's sliding direction reverses (see [`super::passes`] for what a pass
//! is and how the two directions of a test are paired): the passes of a per-sample
//! direction, the friction force oriented so that μ is positive in every pass, and
//! segments split at the reversals.

use super::span::Span;

/// Where a recording's sliding direction reverses.
#[derive(Debug, Clone, Default, PartialEq)]
pub(super) struct Passes {
    /// The first pass's direction as recorded (+1, −1; 0 when nothing slides).
    pub(super) first: i8,
    /// Per reversal, `(end, start)`: one past the last sliding sample of the pass before, and
    /// the first sliding sample of the pass after.
    pub(super) reversals: Vec<(usize, usize)>,
}

impl Passes {
    /// The passes of a per-sample direction (0: not sliding; see [`crate::sliding`]).
    pub(super) fn of(direction: &[i8]) -> Passes {
        let mut out = Passes::default();
        let mut last: Option<(i8, usize)> = None; // direction, one past its last sample
        for (k, &d) in direction.iter().enumerate() {
            if d == 0 {
                continue;
            }
            match last {
                None => out.first = d,
                Some((prev, end)) if prev != d => out.reversals.push((end, k)),
                _ => {}
            }
            last = Some((d, k + 1));
        }
        out
    }

    /// The pass (0-based) sample `k` belongs to: reversals started at or before it.
    pub(super) fn pass_at(&self, k: usize) -> u32 {
        self.reversals.partition_point(|r| r.1 <= k) as u32
    }

    /// `forward` or `reverse` for pass `q` (`None` for a test in one direction).
    pub(super) fn direction_name(&self, q: u32) -> Option<&'static str> {
        (!self.reversals.is_empty()).then_some(if q.is_multiple_of(2) {
            "forward"
        } else {
            "reverse"
        })
    }

    /// Orient the friction force `ft` so that it is positive in every pass: each pass, from
    /// its first sliding sample to the next pass's, multiplied by its direction as recorded
    /// (the stretch before the first pass by the first's). Whether the first pass was
    /// negative as recorded (the channel's sign flipped).
    pub(super) fn orient(&self, direction: &[i8], ft: &mut [f64]) -> bool {
        if self.first == 0 {
            return false;
        }
        let mut from = 0;
        for (q, &(_, start)) in self.reversals.iter().chain([&(0, ft.len())]).enumerate() {
            let sign = if q % 2 == 0 { self.first } else { -self.first };
            if sign < 0 {
                ft[from..start].iter_mut().for_each(|v| *v = -*v);
            }
            from = start;
        }
        debug_assert!(direction.len() == ft.len());
        self.first < 0
    }

    /// The file's note on its passes (none for a test in one direction).
    pub(super) fn note(&self, time_s: &[f64]) -> Option<String> {
        if self.reversals.is_empty() {
            return None;
        }
        let at: Vec<String> = self
            .reversals
            .iter()
            .map(|(e, s)| format!("{:.3}–{:.3} s", time_s[e - 1], time_s[*s]))
            .collect();
        Some(format!(
            "bidirectional test: the sliding direction reverses {} time(s) (at {}); forward is the first pass's direction, every pass is measured on its own with μ as a magnitude, and a forward pass followed by a reverse one is one row, μ the mean of both directions",
            self.reversals.len(),
            at.join(", ")
        ))
    }

    /// `spans` split at every reversal inside them (the stop between the passes left out),
    /// each piece labelled with its pass; a piece that ends or starts at a reversal has the
    /// friction force's fall to zero and rise from it there, which [`trim_ends`] cuts.
    pub(super) fn split(&self, spans: &[Span]) -> Vec<Span> {
        let mut out = Vec::with_capacity(spans.len());
        for sp in spans {
            let mut piece = Span {
                pass: self.pass_at(sp.i),
                ..*sp
            };
            for &(end, start) in self.reversals.iter().filter(|r| r.1 > sp.i && r.1 < sp.j) {
                if end > piece.i {
                    out.push(Span {
                        j: end,
                        unc: (piece.unc.0, 0.0),
                        ..piece
                    });
                }
                piece = Span {
                    i: start,
                    pass: self.pass_at(start),
                    unc: (0.0, sp.unc.1),
                    ..piece
                };
            }
            out.push(piece);
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn passes_split_spans_at_reversals_and_orient_the_force() {
        // forward 0..10, stop 10..12, reverse 12..20
        let mut dir = vec![1i8; 10];
        dir.extend([0, 0]);
        dir.extend([-1i8; 8]);
        let p = Passes::of(&dir);
        assert_eq!(p.first, 1);
        assert_eq!(p.reversals, vec![(10, 12)]);
        let spans = p.split(&[Span::new(0, 20, None)]);
        let got: Vec<(usize, usize, u32)> = spans.iter().map(|s| (s.i, s.j, s.pass)).collect();
        assert_eq!(got, vec![(0, 10, 0), (12, 20, 1)]);
        let mut ft: Vec<f64> = dir.iter().map(|d| *d as f64).collect();
        assert!(!p.orient(&dir, &mut ft));
        assert!(ft[12..].iter().all(|v| *v == 1.0));
        // the first pass negative as recorded: flipped, reverse positive as recorded
        let neg: Vec<i8> = dir.iter().map(|d| -d).collect();
        let q = Passes::of(&neg);
        let mut ft: Vec<f64> = neg.iter().map(|d| 2.0 * *d as f64).collect();
        assert!(q.orient(&neg, &mut ft));
        assert!(ft[..10].iter().chain(&ft[12..]).all(|v| *v == 2.0));
        assert_eq!(q.direction_name(1), Some("reverse"));
        assert_eq!(Passes::of(&[1, 1, 0]).direction_name(0), None);
    }
}
