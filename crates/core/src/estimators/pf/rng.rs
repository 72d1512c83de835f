//! The particle filters' generator ([`PfRng`]), its state words for the saved state, and
//! the six standard normals of one particle's draw.

use super::N;
use crate::numerics::ziggurat::Ziggurat;
use crate::types::State;
use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;

/// The particle filters' generator: xoshiro256++ (Blackman & Vigna), seeded through
/// SplitMix64 by `seed_from_u64`. Chosen over ChaCha8 for speed (the six normals per
/// particle and step were a quarter of a SIR step); statistical quality is ample for
/// Monte Carlo and the stream is fixed by the crate's documented algorithm, so results
/// are reproducible from the seed. Its `jump` (2^128 draws) gives the parallel chunks
/// non-overlapping streams.
pub type PfRng = Xoshiro256PlusPlus;

/// The four 64-bit words of a [`PfRng`]'s state. rand_xoshiro exposes them only through its
/// serde form (a struct of one `[u64; 4]`), read here without naming its field; the result
/// is checked by rebuilding the generator from it. `None` if that ever fails (then the saved
/// state carries zeros, which [`rng_from_state`] refuses, rather than a wrong stream).
pub fn rng_state(rng: &PfRng) -> Option<[u64; 4]> {
    fn words(v: &serde_json::Value, out: &mut Vec<u64>) {
        match v {
            serde_json::Value::Number(n) => out.extend(n.as_u64()),
            serde_json::Value::Array(a) => a.iter().for_each(|x| words(x, out)),
            serde_json::Value::Object(m) => m.values().for_each(|x| words(x, out)),
            _ => {}
        }
    }
    let v = serde_json::to_value(rng).ok()?;
    let mut out = Vec::with_capacity(4);
    words(&v, &mut out);
    let s: [u64; 4] = out.try_into().ok()?;
    (rng_from_state(s).as_ref() == Some(rng)).then_some(s)
}

/// The generator in state `s` (xoshiro256++ state words `s[0..4]`, as the reference
/// implementation names them). `None` for the all-zero state, which xoshiro never reaches.
pub fn rng_from_state(s: [u64; 4]) -> Option<PfRng> {
    if s == [0; 4] {
        return None;
    }
    let mut seed = [0u8; 32];
    for (c, w) in seed.chunks_exact_mut(8).zip(s) {
        c.copy_from_slice(&w.to_le_bytes());
    }
    Some(PfRng::from_seed(seed))
}

/// Six independent standard normals (one batch of [`Ziggurat::fill`]).
#[inline(always)]
pub(super) fn gauss6<R: Rng + ?Sized>(rng: &mut R) -> State {
    let mut e = [0.0; N];
    Ziggurat::get().fill(rng, &mut e);
    State::from(e)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The generator's state words read through serde rebuild the same stream (and are
    /// the reference implementation's: the first output is `rotl(s0 + s3, 23) + s0`).
    #[test]
    fn generator_state_round_trips() {
        use rand::RngCore;
        let mut rng = PfRng::seed_from_u64(42);
        for _ in 0..1000 {
            rng.next_u64();
        }
        let s = rng_state(&rng).expect("state words");
        let want = s[0].wrapping_add(s[3]).rotate_left(23).wrapping_add(s[0]);
        let mut copy = rng_from_state(s).expect("non-zero");
        assert_eq!(copy, rng);
        assert_eq!(copy.next_u64(), want);
        assert_eq!(rng.next_u64(), want);
        assert!(rng_from_state([0; 4]).is_none());
    }
}
