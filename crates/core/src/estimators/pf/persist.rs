//! The particle filter's saved state (see `docs/state-format.md`).

use super::rng::{rng_from_state, rng_state};
use super::ParticleFilter;
use crate::numerics::state::{refuse, Persist, Reader, StateError, Writer};
use std::cell::OnceCell;

/// Saved state (see `docs/state-format.md`): the particle count `n` and the count `m` of
/// per-particle proposal means and covariances (`n` for the unscented kinds, else 0), the
/// prior `x0`, `P0`; per particle the state, proposal mean and covariance, log-weight,
/// weight, log-likelihood and the pairing permutation (u32; the genetic moves shuffle it in
/// place, so its order is state); then the weighted mean, the cached covariance (if
/// computed), the ESS, the initialisation flags, the Gaussian prior and its factor, the
/// move steps' predictive Gaussian (mean, covariance, factor), the generator's four state
/// words and those of every chunk generator of the parallel path (one per 4096 particles
/// from `PARALLEL_MIN_PARTICLES` on, none below), the cached `Q`, its square root and
/// definiteness, and the counters (resamplings, moves tried and accepted). The settings,
/// the worker pool and the unscented proposal's weights are configuration; the `*_tmp`,
/// `idx` and `scratch` buffers and the chunk generators' saved copies are
/// overwritten by every step before they are read, and the transposed copy `soa` is not
/// saved (marked stale by a load).
impl Persist for ParticleFilter {
    fn save_state(&self, w: &mut Writer<'_>) {
        let Self {
            params: _,
            x0,
            p0,
            x,
            xbar,
            pc,
            x_tmp: _,
            xbar_tmp: _,
            pc_tmp: _,
            logw,
            logw_tmp: _,
            w: weights,
            loglik,
            loglik_tmp: _,
            idx,
            pending,
            perm,
            soa: _,
            soa_fresh: _,
            scratch: _,
            mean,
            cov,
            ess,
            awaiting_first,
            awaiting_velocity,
            prior_mode,
            prior_mean,
            prior_cov,
            prior_l,
            pred_mean,
            pred_cov,
            pred_l,
            rng,
            chunk_rng,
            chunk_rng_saved,
            pool: _,
            q_key,
            q_sqrt,
            q_pd,
            ukf: _,
            resamples,
            moves_tried,
            moves_accepted,
        } = self;
        w.usize(x.len());
        w.usize(pc.len());
        w.matrix(x0);
        w.matrix(p0);
        // a pending index-only resampling is saved applied (the layout is unchanged)
        let order = |k: usize| if *pending { idx[k] } else { k };
        (0..x.len()).for_each(|k| w.matrix(&x[order(k)]));
        xbar.iter().for_each(|v| w.matrix(v));
        pc.iter().for_each(|v| w.matrix(v));
        logw.iter().for_each(|v| w.f64(*v));
        weights.iter().for_each(|v| w.f64(*v));
        (0..loglik.len()).for_each(|k| w.f64(loglik[order(k)]));
        perm.iter().for_each(|v| w.u32(*v as u32));
        w.matrix(mean);
        w.opt_matrix(cov.get());
        w.f64(*ess);
        w.bool(*awaiting_first);
        w.bool(*awaiting_velocity);
        w.bool(*prior_mode);
        w.matrix(prior_mean);
        w.matrix(prior_cov);
        w.matrix(prior_l);
        w.matrix(pred_mean);
        w.matrix(pred_cov);
        w.matrix(pred_l);
        for g in core::iter::once(rng).chain(chunk_rng.iter()) {
            for word in rng_state(g).unwrap_or([0; 4]) {
                w.u64(word);
            }
        }
        // the saved copies are rewritten at the start of every step before they are read
        let _ = chunk_rng_saved;
        w.matrix(q_key);
        w.matrix(q_sqrt);
        w.bool(*q_pd);
        w.u64(*resamples);
        w.u64(*moves_tried);
        w.u64(*moves_accepted);
    }

    fn load_state(&mut self, r: &mut Reader<'_>) -> Result<(), StateError> {
        let Self {
            params: _,
            x0,
            p0,
            x,
            xbar,
            pc,
            x_tmp: _,
            xbar_tmp: _,
            pc_tmp: _,
            logw,
            logw_tmp: _,
            w: weights,
            loglik,
            loglik_tmp: _,
            idx,
            pending,
            perm,
            soa: _,
            soa_fresh,
            scratch: _,
            mean,
            cov,
            ess,
            awaiting_first,
            awaiting_velocity,
            prior_mode,
            prior_mean,
            prior_cov,
            prior_l,
            pred_mean,
            pred_cov,
            pred_l,
            rng,
            chunk_rng,
            chunk_rng_saved,
            pool: _,
            q_key,
            q_sqrt,
            q_pd,
            ukf: _,
            resamples,
            moves_tried,
            moves_accepted,
        } = self;
        let n = x.len();
        let _ = idx;
        *soa_fresh = false;
        r.count("particle count", n)?;
        r.count("per-particle proposal count", pc.len())?;
        *x0 = r.matrix("prior mean x0")?;
        *p0 = r.matrix("prior covariance P0")?;
        for v in x.iter_mut() {
            *v = r.finite_matrix("particle")?;
        }
        // the particles were saved with any pending resampling applied
        *pending = false;
        for v in xbar.iter_mut() {
            *v = r.matrix("particle proposal mean")?;
        }
        for v in pc.iter_mut() {
            *v = r.matrix("particle proposal covariance")?;
        }
        for v in logw.iter_mut() {
            *v = r.f64("log-weight")?;
        }
        for v in weights.iter_mut() {
            *v = r.finite("weight")?;
            if *v < 0.0 {
                return Err(refuse(format!("a particle weight is negative ({v})")));
            }
        }
        for v in loglik.iter_mut() {
            *v = r.f64("log-likelihood")?;
        }
        let mut seen = vec![false; n];
        for v in perm.iter_mut() {
            let i = r.u32("pairing permutation")? as usize;
            match seen.get_mut(i) {
                Some(s) if !*s => *s = true,
                _ => {
                    return Err(refuse(format!(
                        "the pairing permutation is not a permutation of 0..{n} (entry {i})"
                    )))
                }
            }
            *v = i;
        }
        *mean = r.matrix("weighted mean")?;
        *cov = match r.opt_matrix("weighted covariance")? {
            Some(c) => OnceCell::from(c),
            None => OnceCell::new(),
        };
        *ess = r.f64("effective sample size")?;
        *awaiting_first = r.bool("awaiting-first-measurement flag")?;
        *awaiting_velocity = r.bool("awaiting-first-velocity flag")?;
        *prior_mode = r.bool("prior-mode flag")?;
        *prior_mean = r.matrix("prior mean")?;
        *prior_cov = r.matrix("prior covariance")?;
        *prior_l = r.matrix("prior covariance factor")?;
        *pred_mean = r.matrix("predictive mean")?;
        *pred_cov = r.matrix("predictive covariance")?;
        *pred_l = r.matrix("predictive covariance factor")?;
        for g in core::iter::once(rng).chain(chunk_rng.iter_mut()) {
            let mut s = [0u64; 4];
            for word in s.iter_mut() {
                *word = r.u64("generator state")?;
            }
            *g = rng_from_state(s).ok_or_else(|| {
                refuse("a particle filter's generator state is all zero (not a xoshiro256++ state)")
            })?;
        }
        chunk_rng_saved.clone_from(chunk_rng);
        *q_key = r.matrix("cached process noise")?;
        *q_sqrt = r.matrix("cached square root of the process noise")?;
        *q_pd = r.bool("process-noise definiteness flag")?;
        *resamples = r.u64("resampling count")?;
        *moves_tried = r.u64("moves tried")?;
        *moves_accepted = r.u64("moves accepted")?;
        Ok(())
    }
}
