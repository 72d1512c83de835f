//! Evaluation engine: scenarios as data, Monte Carlo campaigns, metrics, reports.

pub mod builtin;
pub mod mars;
pub mod metrics;
pub mod pcrlb;
pub mod report;
pub mod results;
pub mod runner;
pub mod scenario;
pub mod sim;
