//! What stores energy, and constant forces, over a window that is not periodic: the
//! nuisance part of the non-periodic energy balance (see [`crate::regressor::nonperiodic`]).
//!
//! Over a window [t_a, t_b] with [g] = g(t_b) − g(t_a):
//!
//! ```text
//!   kinetic, lumped mass m_i per DOF:     m_i · ½[v_i²]                 (unknown m_i)
//!   kinetic, known mass matrix M:         ½[vᵀ M v]                     (moved to b)
//!   potential, stiffness k_e per element: k_e · ½[δ_e²],  δ_e = x_a − x_b (unknown k_e)
//!   potential, known stiffness matrix K:  ½[xᵀ K x]                     (moved to b)
//!   constant force f_i on DOF i:          f_i · [x_i]                   (unknown f_i)
//! ```
//!
//! Each unknown gives one regressor column, named `mass[i]`, `stiffness[label]` and
//! `offset[i]` (1-based DOFs, element labels as in damping terms). A constant force f_i
//! is one that enters the equations of motion on the left, M ẍ + … + f = r: a weight, a
//! preload, or a bias of the force sensor.

use faer::{Mat, MatRef};

use crate::error::{Error, Result, check_finite};
use crate::terms::Element;

/// The kinetic energy of the structure.
#[derive(Debug, Clone, PartialEq)]
pub enum Kinetic {
    /// An unknown lumped mass per DOF (the default): one column each.
    LumpedPerDof,
    /// A known mass matrix M (n × n): ½\[vᵀMv\] is subtracted from the input work.
    Known(Mat<f64>),
    /// No kinetic energy term (a massless or quasi-static system).
    Neglected,
}

/// The potential energy of the structure.
#[derive(Debug, Clone, PartialEq)]
pub enum Potential {
    /// No springs (the default; a drive on a guide).
    Neglected,
    /// An unknown linear stiffness per element: one column each.
    Elements(Vec<Element>),
    /// A known stiffness matrix K (n × n): ½\[xᵀKx\] is subtracted from the input work.
    Known(Mat<f64>),
}

/// The nuisance terms of the non-periodic energy balance.
#[derive(Debug, Clone, PartialEq)]
pub struct StorageModel {
    /// Kinetic energy.
    pub kinetic: Kinetic,
    /// Potential energy.
    pub potential: Potential,
    /// DOFs (0-based) with an unknown constant force.
    pub offsets: Vec<usize>,
}

impl Default for StorageModel {
    /// An unknown lumped mass per DOF, no springs, no constant forces.
    fn default() -> Self {
        StorageModel {
            kinetic: Kinetic::LumpedPerDof,
            potential: Potential::Neglected,
            offsets: Vec::new(),
        }
    }
}

/// The endpoint states of one window: x and v at t_a and t_b (length n each).
pub(crate) struct Endpoints<'a> {
    pub(crate) x_start: &'a [f64],
    pub(crate) x_end: &'a [f64],
    pub(crate) v_start: &'a [f64],
    pub(crate) v_end: &'a [f64],
}

impl StorageModel {
    /// Checks DOF indices and matrix sizes against `dofs`.
    pub fn validate(&self, dofs: usize) -> Result<()> {
        let square = |what: &str, m: &Mat<f64>| -> Result<()> {
            if m.nrows() != dofs || m.ncols() != dofs {
                let found = if m.nrows() != dofs {
                    m.nrows()
                } else {
                    m.ncols()
                };
                return Err(Error::mismatch(format!("{what} size vs DOFs"), dofs, found));
            }
            check_finite(what, m.as_ref())
        };
        if let Kinetic::Known(m) = &self.kinetic {
            square("known mass matrix", m)?;
        }
        match &self.potential {
            Potential::Known(k) => square("known stiffness matrix", k)?,
            Potential::Elements(elements) => {
                if elements.is_empty() {
                    return Err(Error::Empty {
                        what: "stiffness elements".into(),
                    });
                }
                for e in elements {
                    e.validate(dofs, "stiffness")?;
                }
            }
            Potential::Neglected => {}
        }
        for (k, &dof) in self.offsets.iter().enumerate() {
            if dof >= dofs {
                return Err(Error::dof_index(
                    format!("constant force {}", k + 1),
                    dof,
                    dofs,
                ));
            }
            if self.offsets[..k].contains(&dof) {
                return Err(Error::invalid(
                    "offsets",
                    dof as f64 + 1.0,
                    "lists this DOF twice (DOFs 1-based)",
                ));
            }
        }
        Ok(())
    }

    /// Names of the nuisance columns, in column order.
    pub fn coefficient_names(&self, dofs: usize) -> Vec<String> {
        let mut names = Vec::new();
        if self.kinetic == Kinetic::LumpedPerDof {
            names.extend((1..=dofs).map(|i| format!("mass[{i}]")));
        }
        if let Potential::Elements(elements) = &self.potential {
            names.extend(elements.iter().map(|e| format!("stiffness[{}]", e.label)));
        }
        names.extend(self.offsets.iter().map(|d| format!("offset[{}]", d + 1)));
        names
    }

    /// The nuisance columns of one window, and the known stored energy to subtract
    /// from its input work.
    pub(crate) fn columns(&self, ends: &Endpoints<'_>) -> (Vec<f64>, f64) {
        let half_change = |start: f64, end: f64| 0.5 * (end * end - start * start);
        let mut columns = Vec::new();
        let mut known = 0.0;
        match &self.kinetic {
            Kinetic::LumpedPerDof => columns.extend(
                ends.v_start
                    .iter()
                    .zip(ends.v_end)
                    .map(|(a, b)| half_change(*a, *b)),
            ),
            Kinetic::Known(m) => {
                known += quadratic_form(m.as_ref(), ends.v_end)
                    - quadratic_form(m.as_ref(), ends.v_start);
            }
            Kinetic::Neglected => {}
        }
        match &self.potential {
            Potential::Elements(elements) => columns.extend(
                elements
                    .iter()
                    .map(|e| half_change(relative(e, ends.x_start), relative(e, ends.x_end))),
            ),
            Potential::Known(k) => {
                known += quadratic_form(k.as_ref(), ends.x_end)
                    - quadratic_form(k.as_ref(), ends.x_start);
            }
            Potential::Neglected => {}
        }
        columns.extend(
            self.offsets
                .iter()
                .map(|&d| ends.x_end[d] - ends.x_start[d]),
        );
        (columns, known)
    }
}

/// The element's relative displacement x_a − x_b (x_a to ground).
fn relative(element: &Element, x: &[f64]) -> f64 {
    x[element.a] - element.b.map_or(0.0, |b| x[b])
}

/// ½ yᵀ A y.
fn quadratic_form(a: MatRef<'_, f64>, y: &[f64]) -> f64 {
    let n = y.len();
    let mut sum = 0.0;
    for j in 0..n {
        for i in 0..n {
            sum += y[i] * a[(i, j)] * y[j];
        }
    }
    0.5 * sum
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ends<'a>(x: [&'a [f64]; 2], v: [&'a [f64]; 2]) -> Endpoints<'a> {
        Endpoints {
            x_start: x[0],
            x_end: x[1],
            v_start: v[0],
            v_end: v[1],
        }
    }

    /// Hand-computed: two DOFs, lumped masses, one spring between them, an offset on
    /// DOF 2. ½(v_b² − v_a²) per DOF, ½((x1−x2)_b² − (x1−x2)_a²), Δx₂.
    #[test]
    fn columns_by_hand() {
        let storage = StorageModel {
            kinetic: Kinetic::LumpedPerDof,
            potential: Potential::Elements(vec![Element::between(0, 1)]),
            offsets: vec![1],
        };
        assert_eq!(
            storage.coefficient_names(2),
            ["mass[1]", "mass[2]", "stiffness[1-2]", "offset[2]"]
        );
        let (columns, known) = storage.columns(&ends(
            [&[1.0, 0.5], &[2.0, -1.0]],
            [&[1.0, 3.0], &[2.0, 1.0]],
        ));
        assert_eq!(columns, vec![1.5, -4.0, 0.5 * (9.0 - 0.25), -1.5]);
        assert_eq!(known, 0.0);
    }

    /// A known M and K move ½[vᵀMv] + ½[xᵀKx] to the right-hand side: no columns.
    #[test]
    fn known_matrices_give_stored_energy() {
        let storage = StorageModel {
            kinetic: Kinetic::Known(Mat::from_fn(2, 2, |i, j| if i == j { 2.0 } else { 0.0 })),
            potential: Potential::Known(Mat::from_fn(2, 2, |i, j| if i == j { 2.0 } else { -1.0 })),
            offsets: vec![],
        };
        let (columns, known) = storage.columns(&ends(
            [&[0.0, 0.0], &[1.0, 0.0]],
            [&[0.0, 0.0], &[0.0, 3.0]],
        ));
        assert!(columns.is_empty());
        // ½·2·9 + ½·2·1 = 9 + 1.
        assert_eq!(known, 10.0);
    }

    #[test]
    fn rejects_dofs_out_of_range_and_repeats() {
        let storage = StorageModel {
            offsets: vec![3],
            ..StorageModel::default()
        };
        assert!(matches!(
            storage.validate(2),
            Err(Error::DofOutOfRange { dof: 4, .. })
        ));
        let storage = StorageModel {
            offsets: vec![0, 0],
            ..StorageModel::default()
        };
        assert!(matches!(
            storage.validate(2),
            Err(Error::InvalidParameter { .. })
        ));
    }
}
