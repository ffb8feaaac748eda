#![no_main]
//! Fuzz target: see `observer_workbench::fuzzing::cli`.
use libfuzzer_sys::fuzz_target;

fuzz_target!(
    init: observer_workbench::fuzzing::warm_up(),
    |data: &[u8]| observer_workbench::fuzzing::cli(data)
);
