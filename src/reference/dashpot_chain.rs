//! The damping model of a chain of n masses between two walls with a linear dashpot of
//! its own on each of the n + 1 links and quadratic damping on every mass:
//!
//! ```text
//!   dissipated power  P = Σ_e c_e (ẋ_{e−1} − ẋ_e)² + Σ_i q_i |ẋ_i|³,   ẋ_{−1} = ẋ_n = 0,
//! ```
//!
//! coefficients `dashpot[0-1]` … `dashpot[n-(n+1)]`, then the quadratic ones (one per
//! mass or one shared, as asked). The per-dashpot example (one shared d) and the
//! regressor and grid benchmarks (one q per mass, the grid adding Coulomb friction) use
//! it; the noisy chain of issue #8 takes its dashpots ([`chain_dashpots`]).

use crate::model::DampingModel;
use crate::terms::laws::{Linear, Quadratic};
use crate::terms::{Coefficients, Element, Term};

/// A linear dashpot on each link of a chain of `dofs` masses fixed at both ends, walls
/// included: `dofs + 1` coefficients named `name[0-1]` … (one per element).
pub fn chain_dashpots(dofs: usize, name: &str) -> Term {
    Term::on_elements(
        Linear,
        Element::chain_fixed_both_ends(dofs),
        Coefficients::PerElement(name.into()),
    )
}

/// The chain's dashpots (`dashpot[…]`), then quadratic damping q ẋ_i|ẋ_i| on every mass
/// with `quadratic` coefficients (e.g. `Coefficients::PerElement("quad".into())` for one
/// per mass, `Coefficients::Shared("d".into())` for one shared).
pub fn dashpot_chain_model(dofs: usize, quadratic: Coefficients) -> DampingModel {
    DampingModel::new()
        .with(chain_dashpots(dofs, "dashpot"))
        .with(Term::per_dof(Quadratic, dofs, quadratic))
}
