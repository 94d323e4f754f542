//! Tests of the `noise_threshold` module.

use super::*;

#[test]
fn robust_sigma_of_gaussian_samples_is_their_standard_deviation() {
    // Box-Muller from a fixed xorshift stream; sigma 40 (integers lose little).
    let mut stream = crate::test_rng::XorShift::new(0x9E37_79B9_7F4A_7C15);
    let mut uniform = || (stream.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
    let mut v: Vec<i32> = (0..20000)
        .map(|_| {
            let (a, b) = (uniform().max(1e-12), uniform());
            let z = (-2.0 * a.ln()).sqrt() * (2.0 * std::f64::consts::PI * b).cos();
            (100.0 + 40.0 * z).round() as i32
        })
        .collect();
    let sigma = robust_sigma(&mut v).unwrap();
    assert!((sigma - 40.0).abs() < 1.5, "{sigma}");
}

#[test]
fn robust_sigma_ignores_a_minority_of_outliers() {
    let mut v: Vec<i32> = (0..100).map(|i| [-2, -1, 0, 1, 2][i % 5]).collect();
    let clean = robust_sigma(&mut v.clone()).unwrap();
    for x in v.iter_mut().take(30) {
        *x = 500; // an edge inside the band
    }
    let dirty = robust_sigma(&mut v).unwrap();
    assert!(dirty <= 3.0 * clean, "{clean} -> {dirty}");
    assert_eq!(robust_sigma(&mut []), None);
}

#[test]
fn counting_gives_the_selections_result_on_random_samples() {
    let mut stream = crate::test_rng::XorShift::new(0x2545_F491_4F6C_DD1D);
    let mut next = || stream.next_u64();
    let mut histogram = vec![0u32; MAX_HISTOGRAM_SPAN];
    for trial in 0..300 {
        let n = 1 + (next() % 500) as usize;
        // narrow noise, noise with outliers, and spans too wide to count (the fallback)
        let spread = [5u64, 60, 2000, 100_000][trial % 4];
        let v: Vec<i32> = (0..n)
            .map(|_| (next() % (2 * spread + 1)) as i32 - spread as i32)
            .collect();
        let a = robust_sigma(&mut v.clone());
        let b = robust_sigma_counted(&mut v.clone(), &mut histogram);
        assert_eq!(a, b, "trial {trial}, n {n}");
    }
    assert_eq!(robust_sigma_counted(&mut [], &mut histogram), None);
}
