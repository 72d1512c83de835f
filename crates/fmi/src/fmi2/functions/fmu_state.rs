//! The FMU-state functions of FMI 2.0 (get, set, free, serialise, deserialise).

use super::*;

// ---------------------------------------------------------------- FMU state

/// How a state moves between instances, for the messages that refuse a handle.
const TRANSFER: &str = "fmi2SerializeFMUstate / fmi2DeSerializeFMUstate";

/// Copy the instance's complete state (`canGetAndSetFMUstate="true"`; the bytes of
/// [`crate::state`]). `*FMUstate == NULL` allocates a new state; a state this instance
/// made is overwritten in place. Allowed in every state (a state taken in the error state
/// restores the error state).
///
/// # Safety
/// `c` live or null; `FMUstate` null or writable.
pub unsafe fn fmi2GetFMUstate<M: Model>(
    c: fmi2Component,
    FMUstate: *mut fmi2FMUstate,
) -> fmi2Status {
    // SAFETY: contract forwarded; `FMUstate` checked for null.
    unsafe {
        guarded::<M, _>(c, "fmi2GetFMUstate", ANY_STATE, |inst| {
            let out = slice_mut(FMUstate, 1, "FMUstate")?;
            inst.get_fmu_state(&mut out[0])
        })
    }
}

/// Restore a state made by this instance (see [`crate::state`] for what is restored and
/// what is refused). A refused state leaves the instance's data unchanged.
///
/// # Safety
/// `c` live or null.
pub unsafe fn fmi2SetFMUstate<M: Model>(c: fmi2Component, FMUstate: fmi2FMUstate) -> fmi2Status {
    const F: &str = "fmi2SetFMUstate";
    // SAFETY: contract forwarded; the state pointer is only compared, never dereferenced.
    unsafe {
        guarded::<M, _>(c, F, ANY_STATE, |inst| {
            inst.set_fmu_state(FMUstate, F, TRANSFER)
        })
    }
}

/// Free a state (`*FMUstate == NULL` is ignored); `*FMUstate` is set to NULL.
///
/// # Safety
/// `c` live or null; `FMUstate` null or writable.
pub unsafe fn fmi2FreeFMUstate<M: Model>(
    c: fmi2Component,
    FMUstate: *mut fmi2FMUstate,
) -> fmi2Status {
    const F: &str = "fmi2FreeFMUstate";
    // SAFETY: contract forwarded; `FMUstate` checked for null.
    unsafe {
        guarded::<M, _>(c, F, ANY_STATE, |inst| {
            let s = slice_mut(FMUstate, 1, "FMUstate")?;
            inst.free_fmu_state(&mut s[0], F, TRANSFER)
        })
    }
}

/// Size in bytes of a state's serialised form (`canSerializeFMUstate="true"`).
///
/// # Safety
/// `c` live or null; `size` null or writable.
pub unsafe fn fmi2SerializedFMUstateSize<M: Model>(
    c: fmi2Component,
    FMUstate: fmi2FMUstate,
    size: *mut usize,
) -> fmi2Status {
    const F: &str = "fmi2SerializedFMUstateSize";
    // SAFETY: contract forwarded; `size` checked for null.
    unsafe {
        guarded::<M, _>(c, F, ANY_STATE, |inst| {
            let out = slice_mut(size, 1, "size")?;
            out[0] = inst.fmu_state_size(FMUstate, F, TRANSFER)?;
            Ok(())
        })
    }
}

/// Copy a state's serialised form into `serializedState` (`size` bytes, at least
/// [`fmi2SerializedFMUstateSize`]; the state fills the first that many).
///
/// # Safety
/// `c` live or null; `serializedState` null or `size` writable bytes.
pub unsafe fn fmi2SerializeFMUstate<M: Model>(
    c: fmi2Component,
    FMUstate: fmi2FMUstate,
    serializedState: *mut fmi2Byte,
    size: usize,
) -> fmi2Status {
    const F: &str = "fmi2SerializeFMUstate";
    // SAFETY: contract forwarded; pointers checked.
    unsafe {
        guarded::<M, _>(c, F, ANY_STATE, |inst| {
            let b = inst.serialized_fmu_state(
                FMUstate,
                size,
                F,
                TRANSFER,
                "fmi2SerializedFMUstateSize",
            )?;
            let out = slice_mut(serializedState.cast::<u8>(), b.len(), "serializedState")?;
            out.copy_from_slice(b);
            Ok(())
        })
    }
}

/// Make a state from serialised bytes (of this FMU, possibly of another instance or
/// process). The bytes are checked here — length, CRC-32, magic, format version, GUID,
/// structure — and refused with a logged reason; whether the state fits this instance's
/// parameters is checked by [`fmi2SetFMUstate`]. `*FMUstate == NULL` allocates a new
/// state; a state this instance made is overwritten.
///
/// # Safety
/// `c` live or null; `serializedState` null or `size` readable bytes; `FMUstate` null or
/// writable.
pub unsafe fn fmi2DeSerializeFMUstate<M: Model>(
    c: fmi2Component,
    serializedState: *const fmi2Byte,
    size: usize,
    FMUstate: *mut fmi2FMUstate,
) -> fmi2Status {
    const F: &str = "fmi2DeSerializeFMUstate";
    // SAFETY: contract forwarded; pointers checked.
    unsafe {
        guarded::<M, _>(c, F, ANY_STATE, |inst| {
            let out = slice_mut(FMUstate, 1, "FMUstate")?;
            if serializedState.is_null() {
                return Err(error(format!("{F}: serializedState is null")));
            }
            let bytes = slice(serializedState.cast::<u8>(), size, "serializedState")?;
            inst.deserialize_fmu_state(bytes, &mut out[0], F)
        })
    }
}
