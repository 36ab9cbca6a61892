//! Classic fixed-step fourth-order Runge–Kutta for y' = g(t, y):
//!
//!   k1 = g(t, y), k2 = g(t + h/2, y + h k1/2), k3 = g(t + h/2, y + h k2/2),
//!   k4 = g(t + h, y + h k3),  y ← y + h (k1 + 2k2 + 2k3 + k4)/6.

/// Reusable stage buffers for one state dimension.
pub(crate) struct Rk4 {
    k: [Vec<f64>; 4],
    stage: Vec<f64>,
}

impl Rk4 {
    pub fn new(dimension: usize) -> Self {
        Rk4 {
            k: std::array::from_fn(|_| vec![0.0; dimension]),
            stage: vec![0.0; dimension],
        }
    }

    /// Advances `y` from `t` by `h`; `g(t, y, out)` writes y' into `out`.
    pub fn step(
        &mut self,
        t: f64,
        h: f64,
        y: &mut [f64],
        mut g: impl FnMut(f64, &[f64], &mut [f64]),
    ) {
        let [k1, k2, k3, k4] = &mut self.k;
        let stage = &mut self.stage;
        g(t, y, k1);
        for i in 0..y.len() {
            stage[i] = y[i] + 0.5 * h * k1[i];
        }
        g(t + 0.5 * h, stage, k2);
        for i in 0..y.len() {
            stage[i] = y[i] + 0.5 * h * k2[i];
        }
        g(t + 0.5 * h, stage, k3);
        for i in 0..y.len() {
            stage[i] = y[i] + h * k3[i];
        }
        g(t + h, stage, k4);
        for i in 0..y.len() {
            y[i] += h * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]) / 6.0;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// y' = y from y(0) = 1: y(1) = e with error O(h⁴).
    #[test]
    fn integrates_exponential_to_fourth_order() {
        let mut rk = Rk4::new(1);
        let mut y = [1.0];
        let h = 0.01;
        for i in 0..100 {
            rk.step(i as f64 * h, h, &mut y, |_, y, out| out[0] = y[0]);
        }
        assert!((y[0] - std::f64::consts::E).abs() < 1e-9);
    }
}
