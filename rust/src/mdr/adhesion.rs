//! Adhesive MDR contact by Heß's rule (Heß 2011; Popov & Heß 2015, ch. 6): the elements
//! attached to the indenter, settled at each step under a depth or a load.
//!
//! An element attaches when the indenter reaches its free surface (the touch rule: a JKR
//! contact of zero range grows as a hard one) and lets go when its elongation g_i - d
//! exceeds the contact law's detachment elongation at the current contact radius
//! a = (elements attached) dx / 2 — sqrt(2 pi a w / E*) under JKR, which makes the
//! contact's edge a crack in Griffith equilibrium: the JKR solution for any axisymmetric
//! profile. Letting go starts at the outermost element (the largest g), and each release
//! shrinks a and with it the elongation the next element may carry: a pull-off is that
//! cascade running to the last element.

use crate::model::contact_law::ContactLaw;

/// The attached elements of a foundation in adhesive contact.
#[derive(Debug, Clone)]
pub struct Attachment {
    law: ContactLaw,
    /// Contact modulus (Pa) of Heß's rule.
    e_star: f64,
    dx: f64,
    attached: Vec<bool>,
    /// Element indices by profile height, highest first: the order elements let go in.
    by_height: Vec<usize>,
    /// Element indices by free surface, lowest first (reordered at each load step).
    by_surface: Vec<usize>,
    count: usize,
    /// Sum of the free surfaces (m) of the attached elements.
    sum: f64,
}

impl Attachment {
    /// No element attached, on the profile `g` (m, spacing `dx` m) of a body of contact
    /// modulus `e_star` (Pa) in contact by `law`.
    pub fn new(g: &[f64], dx: f64, law: ContactLaw, e_star: f64) -> Self {
        let mut by_height: Vec<usize> = (0..g.len()).collect();
        by_height.sort_by(|&i, &j| g[j].total_cmp(&g[i]));
        Attachment {
            law,
            e_star,
            dx,
            attached: vec![false; g.len()],
            by_surface: by_height.iter().rev().copied().collect(),
            by_height,
            count: 0,
            sum: 0.0,
        }
    }

    /// Whether element `i` is attached.
    pub fn is_attached(&self, i: usize) -> bool {
        self.attached[i]
    }

    /// Number of attached elements.
    pub fn count(&self) -> usize {
        self.count
    }

    /// Sum over the attached elements of d - surface_i (m): their total compression at
    /// depth `d` (m), negative when they pull.
    pub fn compression(&self, d: f64) -> f64 {
        self.count as f64 * d - self.sum
    }

    fn attach(&mut self, i: usize, surface: &[f64]) {
        self.attached[i] = true;
        self.count += 1;
        self.sum += surface[i];
    }

    fn recount(&mut self, surface: &[f64]) {
        self.count = 0;
        self.sum = 0.0;
        for (i, &s) in surface.iter().enumerate() {
            if self.attached[i] {
                self.count += 1;
                self.sum += s;
            }
        }
    }

    /// Lets go the elements whose elongation exceeds the detachment elongation, from the
    /// outside in, at the depth `depth(count, sum)` (m) the attached set gives; whether any
    /// let go.
    fn release(&mut self, g: &[f64], surface: &[f64], depth: impl Fn(usize, f64) -> f64) -> bool {
        let mut released = false;
        for idx in 0..self.by_height.len() {
            let i = self.by_height[idx];
            if !self.attached[i] {
                continue;
            }
            let d = depth(self.count, self.sum);
            let a = 0.5 * self.count as f64 * self.dx;
            if g[i] - d > self.law.detachment_elongation(a, self.e_star) {
                self.attached[i] = false;
                self.count -= 1;
                self.sum -= surface[i];
                released = true;
                if self.count == 0 {
                    break;
                }
            } else {
                break;
            }
        }
        released
    }

    /// Settles the attached set under an indenter at depth `d` (m) on elements of free
    /// surfaces `surface` (m) and profile `g` (m): every touched element attaches, then
    /// elements let go from the outside in.
    pub fn at_depth(&mut self, g: &[f64], surface: &[f64], d: f64) {
        for (i, &s) in surface.iter().enumerate() {
            if !self.attached[i] && s < d {
                self.attached[i] = true;
            }
        }
        self.recount(surface);
        self.release(g, surface, |_, _| d);
    }

    /// Settles the attached set under the load `s` (m: the force over the element
    /// stiffness) and returns the depth (m) that carries it; None when no element stays
    /// attached under a tensile load (the indenter has come off). A zero load without
    /// contact touches the lowest free surface.
    pub fn under_load(&mut self, g: &[f64], surface: &[f64], s: f64) -> Option<f64> {
        self.recount(surface);
        self.by_surface
            .sort_unstable_by(|&i, &j| surface[i].total_cmp(&surface[j]));
        let depth = |count: usize, sum: f64| (s + sum) / count as f64;
        let mut next = 0;
        loop {
            // the touch rule: attach the lowest free surfaces the indenter reaches
            while next < self.by_surface.len() {
                let j = self.by_surface[next];
                if self.attached[j] {
                    next += 1;
                    continue;
                }
                let reaches = if self.count == 0 {
                    s > 0.0
                } else {
                    surface[j] < depth(self.count, self.sum)
                };
                if !reaches {
                    break;
                }
                self.attach(j, surface);
                next += 1;
            }
            if self.count == 0 {
                return (s >= 0.0).then(|| surface[self.by_surface[0]]);
            }
            if !self.release(g, surface, depth) {
                return Some(depth(self.count, self.sum));
            }
            if self.count == 0 {
                return (s >= 0.0).then(|| surface[self.by_surface[0]]);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A flat punch lets go all at once when its elongation reaches sqrt(2 pi a w / E*),
    /// and holds any smaller one.
    #[test]
    fn a_flat_punch_lets_go_at_once() {
        let (n, a, w, e) = (10, 1.0, 0.5, 2.0);
        let g = vec![0.0; n];
        let dx = 2.0 * a / n as f64;
        let law = ContactLaw::Jkr {
            work_of_adhesion: w,
        };
        let mut at = Attachment::new(&g, dx, law, e);
        at.at_depth(&g, &g, 1e-3);
        assert_eq!(at.count(), n);
        let limit = (2.0 * std::f64::consts::PI * a * w / e).sqrt();
        at.at_depth(&g, &g, -0.999 * limit);
        assert_eq!(at.count(), n);
        at.at_depth(&g, &g, -1.001 * limit);
        assert_eq!(at.count(), 0);
    }
}
