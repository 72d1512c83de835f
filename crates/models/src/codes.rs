//! Code lists of Integer parameters that more than one model's table declares: relnav-core's
//! own declarations (the enums' codes, names and descriptions), re-exported under the
//! names the tables use.

pub use relnav_core::nav::config::{
    FRAME_CODES as FRAME_TYPE, NOISE_MODEL_CODES as NOISE_MODEL_TYPE,
};
