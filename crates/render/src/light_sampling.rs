//! Weighing light sampling against a BSDF's own sampling (multiple importance sampling).

/// The power heuristic (β = 2) weight of a strategy with density `a` against one with `b`.
/// Written as a ratio, so that an infinite `a` (a point light, which `b`'s strategy cannot
/// draw) weighs 1 and large densities do not overflow their squares.
pub fn power_heuristic(a: f32, b: f32) -> f32 {
    if a <= 0.0 {
        return 0.0;
    }
    let ratio = b / a;
    1.0 / (1.0 + ratio * ratio)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weights_of_the_two_strategies_sum_to_one() {
        for (a, b) in [(1.0, 1.0), (0.3, 7.0), (1e30, 2e30), (5.0, 0.0)] {
            let sum = power_heuristic(a, b) + power_heuristic(b, a);
            assert!((sum - 1.0).abs() < 1e-6, "{a}, {b}: {sum}");
        }
        assert_eq!(power_heuristic(f32::INFINITY, 3.0), 1.0);
        assert_eq!(power_heuristic(3.0, f32::INFINITY), 0.0);
        assert_eq!(power_heuristic(0.0, 1.0), 0.0);
        assert!((power_heuristic(1.0, 2.0) - 0.2).abs() < 1e-6);
    }
}
