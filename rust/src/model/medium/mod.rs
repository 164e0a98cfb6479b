//! Half-space media. Each has a shear relaxation modulus G(t) (Pa), creep compliance J(t)
//! (1/Pa) and a constant Poisson ratio nu (default 0.5, incompressible): its contact modulus
//! is E*(t) = 2 G(t) / (1 - nu) (4 G for nu = 0.5). The solvers work with E* = 4 G: they step
//! the medium's incompressible equivalent (`Medium::incompressible_equivalent`, moduli and
//! viscosities times 1 / (2 (1 - nu))) as G(t) = G_inf + sum_k G_k exp(-t / tau_k) +
//! eta delta(t) (`Rheology`), the power law as such a series over the time range of a run
//! (`crate::model::medium::power_law`).

pub mod power_law;
pub mod rheology;

use crate::model::medium::power_law::{check_exponent, ln_gamma, PronyOfPowerLaw};
use crate::model::medium::rheology::Rheology;
use crate::support::error::{check_positive, Error, Result};
use serde::{Deserialize, Serialize};

/// A linear (visco)elastic half-space.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(tag = "type", rename_all = "lowercase", deny_unknown_fields)]
pub enum Medium {
    /// Linear elastic: a scene with it is one static contact solve.
    Elastic {
        /// Shear modulus (Pa).
        #[serde(rename = "G")]
        g: f64,
        /// Poisson ratio, -1 < nu <= 0.5 (default 0.5, incompressible).
        #[serde(
            default = "incompressible",
            deserialize_with = "poisson_ratio",
            skip_serializing_if = "is_incompressible"
        )]
        nu: f64,
    },
    /// Newtonian viscous.
    Viscous {
        /// Shear viscosity (Pa s).
        eta: f64,
        /// Poisson ratio, -1 < nu <= 0.5 (default 0.5, incompressible).
        #[serde(
            default = "incompressible",
            deserialize_with = "poisson_ratio",
            skip_serializing_if = "is_incompressible"
        )]
        nu: f64,
    },
    /// Spring G parallel to a dashpot eta.
    KelvinVoigt {
        /// Shear modulus (Pa).
        #[serde(rename = "G")]
        g: f64,
        /// Viscosity (Pa s).
        eta: f64,
        /// Poisson ratio, -1 < nu <= 0.5 (default 0.5, incompressible).
        #[serde(
            default = "incompressible",
            deserialize_with = "poisson_ratio",
            skip_serializing_if = "is_incompressible"
        )]
        nu: f64,
    },
    /// Spring G in series with a dashpot eta (tau = eta / G).
    Maxwell {
        /// Shear modulus (Pa).
        #[serde(rename = "G")]
        g: f64,
        /// Viscosity (Pa s).
        eta: f64,
        /// Poisson ratio, -1 < nu <= 0.5 (default 0.5, incompressible).
        #[serde(
            default = "incompressible",
            deserialize_with = "poisson_ratio",
            skip_serializing_if = "is_incompressible"
        )]
        nu: f64,
    },
    /// Standard linear solid G(t) = G_inf + G1 exp(-t / tau1).
    StandardSolid {
        /// Long-time modulus (Pa).
        #[serde(rename = "G_inf")]
        g_inf: f64,
        /// Relaxing modulus (Pa).
        #[serde(rename = "G1")]
        g1: f64,
        /// Relaxation time (s).
        tau1: f64,
        /// Poisson ratio, -1 < nu <= 0.5 (default 0.5, incompressible).
        #[serde(
            default = "incompressible",
            deserialize_with = "poisson_ratio",
            skip_serializing_if = "is_incompressible"
        )]
        nu: f64,
    },
    /// Generalised Maxwell body G(t) = G_inf + sum_k G_k exp(-t / tau_k).
    Prony {
        /// Long-time modulus (Pa), >= 0.
        #[serde(rename = "G_inf")]
        g_inf: f64,
        /// Terms [G_k (Pa), tau_k (s)].
        terms: Vec<[f64; 2]>,
        /// Poisson ratio, -1 < nu <= 0.5 (default 0.5, incompressible).
        #[serde(
            default = "incompressible",
            deserialize_with = "poisson_ratio",
            skip_serializing_if = "is_incompressible"
        )]
        nu: f64,
    },
    /// Power-law rheology G(t) = G0 (t / t0)^-beta, 0 < beta < 1 (the standard model of
    /// cell rheology); stepped as a Prony series over the run's time range.
    #[serde(rename = "powerlaw")]
    PowerLaw {
        /// Modulus at the reference time t0 (Pa).
        #[serde(rename = "G0")]
        g0: f64,
        /// Exponent, in (0, 1).
        beta: f64,
        /// Reference time (s).
        t0: f64,
        /// Poisson ratio, -1 < nu <= 0.5 (default 0.5, incompressible).
        #[serde(
            default = "incompressible",
            deserialize_with = "poisson_ratio",
            skip_serializing_if = "is_incompressible"
        )]
        nu: f64,
    },
}

/// The Poisson ratio of an incompressible medium, the default.
pub const INCOMPRESSIBLE: f64 = 0.5;

fn incompressible() -> f64 {
    INCOMPRESSIBLE
}

fn is_incompressible(nu: &f64) -> bool {
    *nu == INCOMPRESSIBLE
}

/// Reads nu as a number; an error names it (serde's own messages inside a tagged table do not).
fn poisson_ratio<'de, D: serde::Deserializer<'de>>(d: D) -> std::result::Result<f64, D::Error> {
    f64::deserialize(d).map_err(|e| serde::de::Error::custom(format!("nu (Poisson ratio): {e}")))
}

/// Fails unless -1 < nu <= 0.5 (the Poisson ratio of a stable isotropic solid; 0.5 is
/// incompressible).
pub fn check_poisson_ratio(nu: f64) -> Result<()> {
    if nu > -1.0 && nu <= INCOMPRESSIBLE {
        Ok(())
    } else {
        Err(Error::InvalidInput(format!(
            "nu (Poisson ratio) must satisfy -1 < nu <= 0.5, got {nu}"
        )))
    }
}

/// The kinds of media, as scene files name them (`type`).
pub const KINDS: [&str; 7] = [
    "elastic",
    "viscous",
    "kelvinvoigt",
    "maxwell",
    "standardsolid",
    "prony",
    "powerlaw",
];

/// The parameter names of a medium of kind `kind` (one of `KINDS`) with `terms` Prony terms
/// (only a Prony series has any), in the order of `Medium::parameters`.
pub fn parameter_names(kind: &str, terms: usize) -> Result<Vec<String>> {
    if terms > 0 && kind != "prony" {
        return Err(Error::InvalidInput(format!(
            "only a Prony series has terms, not a medium of kind {kind:?}"
        )));
    }
    let count = match kind {
        "elastic" | "viscous" => 1,
        "kelvinvoigt" | "maxwell" => 2,
        "prony" => 1 + 2 * terms,
        _ => 3,
    };
    let placeholder = Medium::from_ordered(kind, &vec![1.0; count], INCOMPRESSIBLE)?;
    Ok(placeholder
        .parameters()
        .into_iter()
        .map(|(n, _)| n)
        .collect())
}

impl Medium {
    /// Fails on parameters that are not finite and positive (G_inf of a Prony series may
    /// be 0 when it has a term) and on a Poisson ratio outside (-1, 0.5].
    pub fn validate(&self) -> Result<()> {
        let ok = |pairs: &[(&str, f64)]| {
            pairs
                .iter()
                .try_for_each(|(name, v)| check_positive(name, *v))
        };
        check_poisson_ratio(self.nu())?;
        match self {
            Medium::Elastic { g, .. } => ok(&[("G", *g)]),
            Medium::Viscous { eta, .. } => ok(&[("eta", *eta)]),
            Medium::KelvinVoigt { g, eta, .. } | Medium::Maxwell { g, eta, .. } => {
                ok(&[("G", *g), ("eta", *eta)])
            }
            Medium::StandardSolid {
                g_inf, g1, tau1, ..
            } => ok(&[("G_inf", *g_inf), ("G1", *g1), ("tau1", *tau1)]),
            Medium::Prony { g_inf, terms, .. } => {
                if !(g_inf.is_finite() && *g_inf >= 0.0) {
                    return Err(Error::InvalidInput(format!(
                        "G_inf must be finite and >= 0, got {g_inf}"
                    )));
                }
                for t in terms {
                    ok(&[("G_k", t[0]), ("tau_k", t[1])])?;
                }
                if *g_inf == 0.0 && terms.is_empty() {
                    return Err(Error::InvalidInput(
                        "the Prony medium has no stiffness (G_inf = 0 and no terms)".into(),
                    ));
                }
                Ok(())
            }
            Medium::PowerLaw { g0, beta, t0, .. } => {
                ok(&[("G0", *g0), ("t0", *t0)])?;
                check_exponent(*beta)
            }
        }
    }

    /// The Poisson ratio nu (constant in time).
    pub fn nu(&self) -> f64 {
        match *self {
            Medium::Elastic { nu, .. }
            | Medium::Viscous { nu, .. }
            | Medium::KelvinVoigt { nu, .. }
            | Medium::Maxwell { nu, .. }
            | Medium::StandardSolid { nu, .. }
            | Medium::Prony { nu, .. }
            | Medium::PowerLaw { nu, .. } => nu,
        }
    }

    /// The incompressible medium (nu = 0.5) with the same contact modulus
    /// E*(t) = 2 G(t) / (1 - nu): every modulus and viscosity times 1 / (2 (1 - nu)),
    /// relaxation times, the exponent and the reference time kept. The solvers work with
    /// E* = 4 G and take every medium through here (`rheology`, `rheology_over`,
    /// `rheology_tangents`, and the elastic and viscous engines' G and eta); nothing else
    /// scales by nu. The identity for nu = 0.5 (the factor is exactly 1).
    pub fn incompressible_equivalent(&self) -> Result<Medium> {
        self.validate()?;
        let s = 1.0 / (2.0 * (1.0 - self.nu()));
        let nu = INCOMPRESSIBLE;
        Ok(match *self {
            Medium::Elastic { g, .. } => Medium::Elastic { g: s * g, nu },
            Medium::Viscous { eta, .. } => Medium::Viscous { eta: s * eta, nu },
            Medium::KelvinVoigt { g, eta, .. } => Medium::KelvinVoigt {
                g: s * g,
                eta: s * eta,
                nu,
            },
            Medium::Maxwell { g, eta, .. } => Medium::Maxwell {
                g: s * g,
                eta: s * eta,
                nu,
            },
            Medium::StandardSolid {
                g_inf, g1, tau1, ..
            } => Medium::StandardSolid {
                g_inf: s * g_inf,
                g1: s * g1,
                tau1,
                nu,
            },
            Medium::Prony {
                g_inf, ref terms, ..
            } => Medium::Prony {
                g_inf: s * g_inf,
                terms: terms.iter().map(|&[g, tau]| [s * g, tau]).collect(),
                nu,
            },
            Medium::PowerLaw { g0, beta, t0, .. } => Medium::PowerLaw {
                g0: s * g0,
                beta,
                t0,
                nu,
            },
        })
    }

    /// The medium's parameters, named as in the scene model, in a fixed order (a Prony
    /// series: G_inf, G1, tau1, G2, tau2, ...); the Poisson ratio, never fitted, is not one.
    pub fn parameters(&self) -> Vec<(String, f64)> {
        let named = |pairs: &[(&str, f64)]| {
            pairs
                .iter()
                .map(|&(n, v)| (n.to_string(), v))
                .collect::<Vec<_>>()
        };
        match *self {
            Medium::Elastic { g, .. } => named(&[("G", g)]),
            Medium::Viscous { eta, .. } => named(&[("eta", eta)]),
            Medium::KelvinVoigt { g, eta, .. } | Medium::Maxwell { g, eta, .. } => {
                named(&[("G", g), ("eta", eta)])
            }
            Medium::StandardSolid {
                g_inf, g1, tau1, ..
            } => named(&[("G_inf", g_inf), ("G1", g1), ("tau1", tau1)]),
            Medium::Prony {
                g_inf, ref terms, ..
            } => {
                let mut out = named(&[("G_inf", g_inf)]);
                for (k, t) in terms.iter().enumerate() {
                    out.push((format!("G{}", k + 1), t[0]));
                    out.push((format!("tau{}", k + 1), t[1]));
                }
                out
            }
            Medium::PowerLaw { g0, beta, t0, .. } => {
                named(&[("G0", g0), ("beta", beta), ("t0", t0)])
            }
        }
    }

    /// The medium of kind `kind` (one of `KINDS`) whose parameters, named as `parameters`
    /// names them, are `values` (in any order), with Poisson ratio `nu`; validated. A missing,
    /// repeated or unknown name is an error that lists the kind's names.
    pub fn from_parameters(kind: &str, values: &[(String, f64)], nu: f64) -> Result<Medium> {
        let terms = if kind == "prony" {
            values.len().saturating_sub(1) / 2
        } else {
            0
        };
        let names = parameter_names(kind, terms)?;
        let mut ordered = Vec::with_capacity(names.len());
        for name in &names {
            let mut found = values.iter().filter(|(n, _)| n == name);
            match (found.next(), found.next()) {
                (Some(&(_, v)), None) => ordered.push(v),
                _ => {
                    return Err(Error::InvalidInput(format!(
                        "a {kind} medium needs the parameters {names:?} once each, got {:?}",
                        values.iter().map(|(n, _)| n).collect::<Vec<_>>()
                    )))
                }
            }
        }
        if values.len() != names.len() {
            return Err(Error::InvalidInput(format!(
                "a {kind} medium needs the parameters {names:?} once each, got {:?}",
                values.iter().map(|(n, _)| n).collect::<Vec<_>>()
            )));
        }
        Medium::from_values(kind, &ordered, nu)
    }

    /// The medium of kind `kind` (one of `KINDS`) from its parameters in the order of
    /// `parameters` (a Prony series: G_inf, G1, tau1, G2, ...), with Poisson ratio `nu`;
    /// validated.
    pub fn from_values(kind: &str, values: &[f64], nu: f64) -> Result<Medium> {
        let medium = Medium::from_ordered(kind, values, nu)?;
        medium.validate()?;
        Ok(medium)
    }

    /// The medium of kind `kind` from its parameters in the order of `parameters`
    /// (unvalidated); an unknown kind or a wrong count is an error.
    fn from_ordered(kind: &str, v: &[f64], nu: f64) -> Result<Medium> {
        let wrong = || {
            Error::InvalidInput(format!(
                "a {kind} medium cannot have the {} parameters {v:?}",
                v.len()
            ))
        };
        Ok(match (kind, v) {
            ("elastic", &[g]) => Medium::Elastic { g, nu },
            ("viscous", &[eta]) => Medium::Viscous { eta, nu },
            ("kelvinvoigt", &[g, eta]) => Medium::KelvinVoigt { g, eta, nu },
            ("maxwell", &[g, eta]) => Medium::Maxwell { g, eta, nu },
            ("standardsolid", &[g_inf, g1, tau1]) => Medium::StandardSolid {
                g_inf,
                g1,
                tau1,
                nu,
            },
            ("prony", [g_inf, rest @ ..]) if rest.len() % 2 == 0 => Medium::Prony {
                g_inf: *g_inf,
                terms: rest.chunks(2).map(|t| [t[0], t[1]]).collect(),
                nu,
            },
            ("powerlaw", &[g0, beta, t0]) => Medium::PowerLaw { g0, beta, t0, nu },
            (k, _) if KINDS.contains(&k) => return Err(wrong()),
            _ => {
                return Err(Error::InvalidInput(format!(
                    "unknown medium kind {kind:?}; the kinds are {KINDS:?}"
                )))
            }
        })
    }

    /// The medium's kind, as scene files name it (one of `KINDS`).
    pub fn kind(&self) -> &'static str {
        match self {
            Medium::Elastic { .. } => "elastic",
            Medium::Viscous { .. } => "viscous",
            Medium::KelvinVoigt { .. } => "kelvinvoigt",
            Medium::Maxwell { .. } => "maxwell",
            Medium::StandardSolid { .. } => "standardsolid",
            Medium::Prony { .. } => "prony",
            Medium::PowerLaw { .. } => "powerlaw",
        }
    }

    /// The solvers' series over times [t_lo, t_hi] (s): the incompressible equivalent as
    /// G_inf + Prony terms + eta delta(t); exact for every medium but the power law, whose
    /// series holds there within `power_law::RELATIVE_ERROR`.
    pub fn rheology_over(&self, t_lo: f64, t_hi: f64) -> Result<Rheology> {
        self.incompressible_equivalent()?.series_over(t_lo, t_hi)
    }

    /// The medium's own series over [t_lo, t_hi] (s), moduli unscaled.
    fn series_over(&self, t_lo: f64, t_hi: f64) -> Result<Rheology> {
        match *self {
            Medium::PowerLaw { g0, beta, t0, .. } => {
                Ok(PronyOfPowerLaw::new(g0, beta, t0, t_lo, t_hi)?.rheology)
            }
            _ => self.series(),
        }
    }

    /// The series of `rheology_over` and its derivatives (same shape: d G_inf, d (G_k, tau_k),
    /// d eta) with respect to the natural logarithm of each parameter of `parameters` (the
    /// derivatives in the logarithms of the medium's moduli equal those in the logarithms of
    /// the equivalent's, which differ by a constant factor).
    pub fn rheology_tangents(&self, t_lo: f64, t_hi: f64) -> Result<(Rheology, Vec<Rheology>)> {
        let m = self.incompressible_equivalent()?;
        let r = m.series_over(t_lo, t_hi)?;
        let zero = Rheology {
            g_inf: 0.0,
            terms: vec![(0.0, 0.0); r.terms.len()],
            eta: 0.0,
        };
        let with = |f: &dyn Fn(&mut Rheology)| {
            let mut d = zero.clone();
            f(&mut d);
            d
        };
        let scaled = |by: f64| Rheology {
            g_inf: by * r.g_inf,
            terms: r.terms.iter().map(|&(g, _)| (by * g, 0.0)).collect(),
            eta: by * r.eta,
        };
        Ok((
            r.clone(),
            match m {
                Medium::Elastic { g, .. } => vec![with(&|d| d.g_inf = g)],
                Medium::Viscous { eta, .. } => vec![with(&|d| d.eta = eta)],
                Medium::KelvinVoigt { g, eta, .. } => {
                    vec![with(&|d| d.g_inf = g), with(&|d| d.eta = eta)]
                }
                Medium::Maxwell { g, eta, .. } => {
                    // G1 = G, tau1 = eta / G
                    let tau = eta / g;
                    vec![
                        with(&|d| d.terms[0] = (g, -tau)),
                        with(&|d| d.terms[0] = (0.0, tau)),
                    ]
                }
                Medium::StandardSolid {
                    g_inf, g1, tau1, ..
                } => vec![
                    with(&|d| d.g_inf = g_inf),
                    with(&|d| d.terms[0].0 = g1),
                    with(&|d| d.terms[0].1 = tau1),
                ],
                Medium::Prony {
                    g_inf, ref terms, ..
                } => {
                    let mut out = vec![with(&|d| d.g_inf = g_inf)];
                    for (k, t) in terms.iter().enumerate() {
                        out.push(with(&|d| d.terms[k].0 = t[0]));
                        out.push(with(&|d| d.terms[k].1 = t[1]));
                    }
                    out
                }
                Medium::PowerLaw { g0, beta, t0, .. } => {
                    let d_beta = PronyOfPowerLaw::new(g0, beta, t0, t_lo, t_hi)?.d_beta();
                    // the series scales with G0 t0^beta; d/d ln beta = beta d/d beta
                    let mut d_log_beta = d_beta;
                    d_log_beta.g_inf *= beta;
                    d_log_beta.eta *= beta;
                    for t in &mut d_log_beta.terms {
                        t.0 *= beta;
                        t.1 *= beta;
                    }
                    vec![scaled(1.0), d_log_beta, scaled(beta)]
                }
            },
        ))
    }

    /// `rheology_tangents` with the derivatives of the parameters named in `names` only, in
    /// that order; an unknown name is an error that lists the medium's names.
    pub fn rheology_tangents_of(
        &self,
        names: &[String],
        t_lo: f64,
        t_hi: f64,
    ) -> Result<(Rheology, Vec<Rheology>)> {
        let (r, all) = self.rheology_tangents(t_lo, t_hi)?;
        let known: Vec<String> = self.parameters().into_iter().map(|(n, _)| n).collect();
        let picked = names
            .iter()
            .map(|name| match known.iter().position(|k| k == name) {
                Some(j) => Ok(all[j].clone()),
                None => Err(Error::InvalidInput(format!(
                    "the medium has no parameter {name:?}; its parameters are {known:?}"
                ))),
            })
            .collect::<Result<Vec<_>>>()?;
        Ok((r, picked))
    }

    /// Whether the medium has a dashpot in parallel (viscous, Kelvin–Voigt): its stress is
    /// unbounded under a jump of strain.
    pub fn has_dashpot(&self) -> bool {
        matches!(self, Medium::Viscous { .. } | Medium::KelvinVoigt { .. })
    }

    /// The solvers' series: the incompressible equivalent as G_inf + Prony terms +
    /// eta delta(t); the power law, which needs a time range, is refused (`rheology_over`).
    pub fn rheology(&self) -> Result<Rheology> {
        self.incompressible_equivalent()?.series()
    }

    /// The medium's own shear modulus as G_inf + Prony terms + eta delta(t), unscaled (the
    /// solvers step `rheology`, the incompressible equivalent's); the power law is refused.
    pub fn series(&self) -> Result<Rheology> {
        self.validate()?;
        match self {
            Medium::Elastic { g, .. } => Rheology::new(*g, vec![], 0.0),
            Medium::Viscous { eta, .. } => Rheology::new(0.0, vec![], *eta),
            Medium::KelvinVoigt { g, eta, .. } => Rheology::new(*g, vec![], *eta),
            Medium::Maxwell { g, eta, .. } => Rheology::new(0.0, vec![(*g, eta / g)], 0.0),
            Medium::StandardSolid { g_inf, g1, tau1, .. } => {
                Rheology::new(*g_inf, vec![(*g1, *tau1)], 0.0)
            }
            Medium::Prony { g_inf, terms, .. } => {
                Rheology::new(*g_inf, terms.iter().map(|t| (t[0], t[1])).collect(), 0.0)
            }
            Medium::PowerLaw { .. } => Err(Error::InvalidInput(
                "a power-law medium is stepped as a Prony series over a time range: use rheology_over".into(),
            )),
        }
    }

    /// Shear relaxation modulus G(t) (Pa) for t > 0 (a dashpot's delta at t = 0 left out);
    /// the contact modulus is 2 G(t) / (1 - nu).
    pub fn relaxation_modulus(&self, t: f64) -> Result<f64> {
        if let Medium::PowerLaw { g0, beta, t0, .. } = *self {
            self.validate()?;
            return Ok(g0 * (t / t0).powf(-beta));
        }
        let r = self.series()?;
        Ok(r.g_inf
            + r.terms
                .iter()
                .map(|(g, tau)| g * (-t / tau).exp())
                .sum::<f64>())
    }

    /// Shear creep compliance J(t) (1/Pa): the shear strain under a unit step of shear
    /// stress. Closed forms, and for a Prony series exact-exponential stepping of the
    /// hereditary law on a fine geometric time grid.
    pub fn creep_compliance(&self, t: f64) -> Result<f64> {
        self.validate()?;
        if !(t.is_finite() && t >= 0.0) {
            return Err(Error::InvalidInput(format!(
                "creep time must be finite and >= 0, got {t}"
            )));
        }
        Ok(match *self {
            Medium::Elastic { g, .. } => 1.0 / g,
            Medium::Viscous { eta, .. } => t / eta,
            Medium::KelvinVoigt { g, eta, .. } => -(-g * t / eta).exp_m1() / g,
            Medium::Maxwell { g, eta, .. } => 1.0 / g + t / eta,
            Medium::StandardSolid {
                g_inf, g1, tau1, ..
            } => {
                let g0 = g_inf + g1;
                1.0 / g_inf + (1.0 / g0 - 1.0 / g_inf) * (-g_inf * t / (g0 * tau1)).exp()
            }
            Medium::Prony { .. } => prony_creep(&self.series()?, t),
            // J(t) = (t / t0)^beta / (G0 Gamma(1 - beta) Gamma(1 + beta))
            Medium::PowerLaw { g0, beta, t0, .. } => {
                (t / t0).powf(beta) / g0 / (ln_gamma(1.0 - beta) + ln_gamma(1.0 + beta)).exp()
            }
        })
    }

    /// Whether the medium is elastic (no time dependence).
    pub fn is_elastic(&self) -> bool {
        matches!(self, Medium::Elastic { .. })
    }
}

/// J(t) of a Prony series (no dashpot): the unit-stress response stepped exactly for a
/// strain varying linearly over each of 20000 geometric steps from 1e-6 min tau_k to t
/// (below 1e-12 min tau_k its first-order series, exact to round-off there).
fn prony_creep(r: &Rheology, t: f64) -> f64 {
    let g0 = r.g_inf + r.terms.iter().map(|(g, _)| g).sum::<f64>();
    let mut x = 1.0 / g0;
    if t <= 0.0 {
        return x;
    }
    let tau_min = r
        .terms
        .iter()
        .map(|&(_, tau)| tau)
        .fold(f64::INFINITY, f64::min);
    if t < 1e-12 * tau_min {
        // J(t) = 1/G0 + t sum(g_k / tau_k) / G0^2 + O((t / tau)^2): exact to round-off here,
        // where a geometric grid from below t would underflow
        let rate: f64 = r.terms.iter().map(|&(g, tau)| g / tau).sum();
        return x + t * rate / (g0 * g0);
    }
    let tau_min = tau_min.min(t);
    let start = (tau_min * 1e-6).min(0.5 * t);
    let steps = 20000;
    let ratio = (t / start).powf(1.0 / (steps - 1) as f64);
    let mut q: Vec<f64> = r.terms.iter().map(|(g, _)| g * x).collect();
    let mut prev = 0.0;
    for k in 0..steps {
        let now = if k == steps - 1 {
            t
        } else {
            start * ratio.powi(k)
        };
        let dt = now - prev;
        prev = now;
        let (mut history, mut gain_sum) = (0.0, 0.0);
        for (i, &(g, tau)) in r.terms.iter().enumerate() {
            let e = (-dt / tau).exp();
            let a = g * mean_decay(dt / tau);
            history += e * q[i];
            gain_sum += a;
        }
        let x_new = (1.0 - (history - gain_sum * x)) / (r.g_inf + gain_sum);
        for (i, &(g, tau)) in r.terms.iter().enumerate() {
            let a = g * mean_decay(dt / tau);
            q[i] = (-dt / tau).exp() * q[i] + a * (x_new - x);
        }
        x = x_new;
    }
    x
}

/// (1 - e^-x) / x, the mean of e^-s over s in [0, x]: 1 - x/2 below x = 1e-8, where the
/// quotient would lose its digits (and is 0/0 or overflows for subnormal steps).
fn mean_decay(x: f64) -> f64 {
    if x < 1e-8 {
        1.0 - 0.5 * x
    } else {
        -(-x).exp_m1() / x
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The power law's tangents in ln G0, ln beta and ln t0 against central differences of
    /// its series' coefficients (step 1e-6: ~1e-10 relative truncation), the slow term's
    /// relaxation time included.
    #[test]
    fn power_law_tangents_match_central_differences() {
        let at = |p: [f64; 3]| Medium::PowerLaw {
            g0: p[0].exp(),
            beta: p[1].exp(),
            t0: p[2].exp(),
            nu: 0.3,
        };
        let (t_lo, t_hi) = (1e-3, 2.0);
        let base = [1e3f64.ln(), 0.2f64.ln(), 0.7f64.ln()];
        let (_, tangents) = at(base).rheology_tangents(t_lo, t_hi).unwrap();
        let coefficients = |r: &Rheology| {
            let mut v = vec![r.g_inf, r.eta];
            v.extend(r.terms.iter().flat_map(|&(g, tau)| [g, tau]));
            v
        };
        let h = 1e-6;
        for (j, tangent) in tangents.iter().enumerate() {
            let (mut up, mut down) = (base, base);
            up[j] += h;
            down[j] -= h;
            let plus = coefficients(&at(up).rheology_over(t_lo, t_hi).unwrap());
            let minus = coefficients(&at(down).rheology_over(t_lo, t_hi).unwrap());
            for (k, (analytic, (a, b))) in coefficients(tangent)
                .iter()
                .zip(plus.iter().zip(&minus))
                .enumerate()
            {
                let numeric = (a - b) / (2.0 * h);
                assert!(
                    (analytic - numeric).abs() <= 1e-7 * a.abs().max(numeric.abs()),
                    "parameter {j}, coefficient {k}: {analytic} vs {numeric}"
                );
            }
        }
    }

    /// The stepped Prony compliance of a one-term series is the standard solid's closed form.
    #[test]
    fn prony_creep_matches_the_standard_solid() {
        let sls = Medium::StandardSolid {
            g_inf: 1.0,
            g1: 3.0,
            tau1: 0.5,
            nu: INCOMPRESSIBLE,
        };
        let prony = Medium::Prony {
            g_inf: 1.0,
            terms: vec![[3.0, 0.5]],
            nu: INCOMPRESSIBLE,
        };
        for t in [0.0, 5e-324, 1e-308, 1e-300, 1e-13, 1e-12, 0.1, 1.0, 7.0] {
            let (a, b) = (
                sls.creep_compliance(t).unwrap(),
                prony.creep_compliance(t).unwrap(),
            );
            assert!((a - b).abs() < 1e-6 * a, "t = {t}: {a} vs {b}");
        }
    }

    /// Every kind rebuilds from its own parameters by name and by order, and its names are
    /// `parameter_names`'; a missing or unknown name is refused with the kind's names.
    #[test]
    fn media_rebuild_from_their_named_parameters() {
        let media = [
            Medium::Elastic { g: 2.0, nu: 0.3 },
            Medium::Viscous {
                eta: 1.5,
                nu: INCOMPRESSIBLE,
            },
            Medium::KelvinVoigt {
                g: 1.0,
                eta: 0.5,
                nu: 0.2,
            },
            Medium::Maxwell {
                g: 2.0,
                eta: 1.0,
                nu: INCOMPRESSIBLE,
            },
            Medium::StandardSolid {
                g_inf: 1.0,
                g1: 3.0,
                tau1: 0.5,
                nu: 0.4,
            },
            Medium::Prony {
                g_inf: 0.5,
                terms: vec![[1.0, 0.1], [2.0, 2.0]],
                nu: INCOMPRESSIBLE,
            },
            Medium::PowerLaw {
                g0: 2.0,
                beta: 0.2,
                t0: 1.0,
                nu: 0.1,
            },
        ];
        for m in &media {
            let named = m.parameters();
            let terms = match m {
                Medium::Prony { terms, .. } => terms.len(),
                _ => 0,
            };
            let names: Vec<String> = named.iter().map(|(n, _)| n.clone()).collect();
            assert_eq!(parameter_names(m.kind(), terms).unwrap(), names);
            let reversed: Vec<(String, f64)> = named.iter().rev().cloned().collect();
            assert_eq!(
                &Medium::from_parameters(m.kind(), &reversed, m.nu()).unwrap(),
                m
            );
            let values: Vec<f64> = named.iter().map(|&(_, v)| v).collect();
            assert_eq!(&Medium::from_values(m.kind(), &values, m.nu()).unwrap(), m);
            assert!(KINDS.contains(&m.kind()));
        }
        let wrong = [("G".to_string(), 1.0), ("tau".to_string(), 1.0)];
        let e = Medium::from_parameters("maxwell", &wrong, 0.5).unwrap_err();
        assert!(e.to_string().contains(r#"["G", "eta"]"#), "{e}");
        assert!(Medium::from_values("gel", &[1.0], 0.5).is_err());
        assert!(parameter_names("maxwell", 2).is_err());
    }

    #[test]
    fn bad_media_are_refused() {
        for m in [
            Medium::Viscous {
                eta: 0.0,
                nu: INCOMPRESSIBLE,
            },
            Medium::Maxwell {
                g: 1.0,
                eta: f64::NAN,
                nu: INCOMPRESSIBLE,
            },
            Medium::Prony {
                g_inf: 0.0,
                terms: vec![],
                nu: INCOMPRESSIBLE,
            },
        ] {
            assert!(matches!(m.validate(), Err(Error::InvalidInput(_))));
        }
    }

    /// A Poisson ratio outside (-1, 0.5] is refused with an error naming nu.
    #[test]
    fn poisson_ratios_outside_the_range_are_refused() {
        for nu in [0.5000001, 0.6, -1.0, -1.5, f64::NAN, f64::INFINITY] {
            let m = Medium::Elastic { g: 1.0, nu };
            match m.validate() {
                Err(Error::InvalidInput(text)) => assert!(text.contains("nu"), "{text}"),
                other => panic!("nu = {nu}: {other:?}"),
            }
        }
        for nu in [0.5, 0.3, 0.0, -0.999] {
            Medium::Elastic { g: 1.0, nu }.validate().unwrap();
        }
    }

    /// nu is optional in the scene model (default 0.5) and written only when it is not 0.5,
    /// so that scenes of incompressible media keep their text.
    #[test]
    fn nu_defaults_to_one_half_and_is_written_only_when_set() {
        let m: Medium = serde_json::from_str(r#"{"type": "elastic", "G": 2.0}"#).unwrap();
        assert_eq!(m.nu(), 0.5);
        assert_eq!(
            serde_json::to_string(&m).unwrap(),
            r#"{"type":"elastic","G":2.0}"#
        );
        let m: Medium = serde_json::from_str(
            r#"{"type": "standardsolid", "G_inf": 1, "G1": 2, "tau1": 3, "nu": 0.3}"#,
        )
        .unwrap();
        assert_eq!(m.nu(), 0.3);
        let back: Medium = serde_json::from_str(&serde_json::to_string(&m).unwrap()).unwrap();
        assert_eq!(back, m);
    }

    /// The equivalent of nu = 0.3 has the contact modulus 2 G / (1 - nu) as 4 G*: its moduli
    /// and viscosities are G / 1.4, its times the same; nu = 0.5 is the medium itself.
    #[test]
    fn the_incompressible_equivalent_has_the_same_contact_modulus() {
        let m = Medium::Prony {
            g_inf: 1.5,
            terms: vec![[2.0, 0.25], [0.5, 4.0]],
            nu: 0.3,
        };
        let e = m.incompressible_equivalent().unwrap();
        assert_eq!(e.nu(), 0.5);
        for t in [0.01, 0.3, 5.0] {
            let contact = 2.0 * m.relaxation_modulus(t).unwrap() / (1.0 - 0.3);
            let solvers = 4.0 * e.relaxation_modulus(t).unwrap();
            assert!(
                (contact / solvers - 1.0).abs() < 1e-15,
                "{contact} vs {solvers}"
            );
        }
        let Medium::Prony { terms, .. } = &e else {
            panic!("{e:?}")
        };
        assert_eq!([terms[0][1], terms[1][1]], [0.25, 4.0]);
        let kv = Medium::KelvinVoigt {
            g: 3.0,
            eta: 7.0,
            nu: 0.5,
        };
        assert_eq!(kv.incompressible_equivalent().unwrap(), kv);
        assert_eq!(
            kv.rheology().unwrap(),
            Rheology::new(3.0, vec![], 7.0).unwrap()
        );
    }
}
