//! Exact signs of small polynomials in `f64` inputs, by Shewchuk's floating-point expansions
//! (error-free sums and products, Dekker's split): the fallback of the predicates in
//! [`crate::predicates`] that `robust` does not provide (a point against a ray given by its
//! direction, a point of a segment at a given height against such a ray). An expansion is a
//! sum of non-overlapping doubles in increasing magnitude; its sign is the sign of its largest
//! component. Exact as long as no intermediate overflows or underflows, which the coordinate
//! domain ([`crate::domain`]) guarantees for the degree-3 polynomials used here.

/// `a + b` as `(sum, error)` exactly (Knuth's two-sum).
#[inline]
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let x = a + b;
    let bv = x - a;
    let av = x - bv;
    (x, (a - av) + (b - bv))
}

/// Dekker's split of `a` into two halves of 26 bits each.
#[inline]
fn split(a: f64) -> (f64, f64) {
    const SPLITTER: f64 = 134_217_729.0; // 2^27 + 1
    let c = SPLITTER * a;
    let big = c - a;
    let hi = c - big;
    (hi, a - hi)
}

/// `a * b` as `(product, error)` exactly (Dekker's two-product).
#[inline]
fn two_product(a: f64, b: f64) -> (f64, f64) {
    let x = a * b;
    let (ah, al) = split(a);
    let (bh, bl) = split(b);
    let err = al * bl - (((x - ah * bh) - al * bh) - ah * bl);
    (x, err)
}

/// A floating-point expansion: the exact sum of its components (non-overlapping, increasing
/// magnitude, zeros dropped).
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct Expansion(Vec<f64>);

impl Expansion {
    /// The exact difference `a - b`.
    pub(crate) fn diff(a: f64, b: f64) -> Expansion {
        let mut e = Expansion::default();
        e.grow(a);
        e.grow(-b);
        e
    }

    /// Adds one double exactly (Shewchuk's Grow-Expansion with zero elimination).
    fn grow(&mut self, b: f64) {
        let mut q = b;
        let mut out = Vec::with_capacity(self.0.len() + 1);
        for &h in &self.0 {
            let (s, e) = two_sum(q, h);
            if e != 0.0 {
                out.push(e);
            }
            q = s;
        }
        if q != 0.0 {
            out.push(q);
        }
        self.0 = out;
    }

    /// The exact sum.
    pub(crate) fn add(&self, other: &Expansion) -> Expansion {
        let mut e = self.clone();
        for &c in &other.0 {
            e.grow(c);
        }
        e
    }

    /// The exact negation.
    pub(crate) fn neg(&self) -> Expansion {
        Expansion(self.0.iter().map(|c| -c).collect())
    }

    /// The exact product.
    pub(crate) fn mul(&self, other: &Expansion) -> Expansion {
        let mut e = Expansion::default();
        for &a in &self.0 {
            for &b in &other.0 {
                let (p, err) = two_product(a, b);
                e.grow(err);
                e.grow(p);
            }
        }
        e
    }

    /// The exact product with one double.
    pub(crate) fn scale(&self, b: f64) -> Expansion {
        self.mul(&Expansion(if b == 0.0 { vec![] } else { vec![b] }))
    }

    /// The sign of the exact value: -1, 0 or 1.
    pub(crate) fn sign(&self) -> f64 {
        self.0.last().map_or(0.0, |c| c.signum())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sums_and_products_keep_every_bit() {
        // 1 + 2^-80 - 1 is 2^-80 exactly, which plain doubles lose.
        let tiny = 2f64.powi(-80);
        let e = Expansion::diff(1.0, -tiny).add(&Expansion::diff(0.0, 1.0));
        assert_eq!(e.0, vec![tiny]);
        // (1 + 2^-52)^2 - 1 - 2^-51 = 2^-104.
        let a = Expansion::diff(1.0, -(2f64.powi(-52)));
        let sq = a.mul(&a).add(&Expansion::diff(-1.0, 2f64.powi(-51)));
        assert_eq!(sq.sign(), 1.0);
        assert_eq!(sq.0.iter().sum::<f64>(), 2f64.powi(-104));
        assert_eq!(a.neg().sign(), -1.0);
        assert_eq!(a.scale(0.0).sign(), 0.0);
    }
}
