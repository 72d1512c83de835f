//! The exported `fmi2*` entry points: [`crate::export_fmi2`] defines every FMI 2.0 common
//! and co-simulation function, unprefixed, for one [`crate::model::Model`], forwarding to
//! the generic implementations of [`crate::fmi2::functions`]. Only the FMUs' shared
//! libraries (`fmu/relnav`, `fmu/plant`, `fmu/guidance`) invoke it, one model each, and
//! the Rust tests and tools that call the `fmi2*` functions as a master would (each in its
//! own binary): no library crate exports `fmi2*` symbols, so any set of FMUs builds in one
//! cargo invocation.

/// Export the FMI 2.0 co-simulation functions of the [`Model`](crate::model::Model)
/// `$model` from the crate that invokes it (at most once per binary: the symbols are
/// unprefixed).
#[macro_export]
macro_rules! export_fmi2 {
    ($model:ty) => {
        #[doc = concat!("`fmi2GetTypesPlatform` (FMI 2.0).")]
        #[no_mangle]
        pub extern "C" fn fmi2GetTypesPlatform() -> *const ::std::ffi::c_char {
            $crate::fmi2::functions::fmi2GetTypesPlatform()
        }
        #[doc = concat!("`fmi2GetVersion` (FMI 2.0).")]
        #[no_mangle]
        pub extern "C" fn fmi2GetVersion() -> *const ::std::ffi::c_char {
            $crate::fmi2::functions::fmi2GetVersion()
        }
        #[doc = concat!("`fmi2Instantiate` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2Instantiate(
            instanceName: $crate::fmi2::types::fmi2String,
            fmuType: ::std::ffi::c_int,
            fmuGUID: $crate::fmi2::types::fmi2String,
            fmuResourceLocation: $crate::fmi2::types::fmi2String,
            functions: *const $crate::fmi2::types::fmi2CallbackFunctions,
            visible: $crate::fmi2::types::fmi2Boolean,
            loggingOn: $crate::fmi2::types::fmi2Boolean,
        ) -> $crate::fmi2::types::fmi2Component {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi2::functions::fmi2Instantiate::<$model>(instanceName, fmuType, fmuGUID, fmuResourceLocation, functions, visible, loggingOn) }
        }
        #[doc = concat!("`fmi2FreeInstance` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2FreeInstance(
            c: $crate::fmi2::types::fmi2Component,
        )  {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi2::functions::fmi2FreeInstance::<$model>(c) }
        }
        #[doc = concat!("`fmi2SetDebugLogging` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2SetDebugLogging(
            c: $crate::fmi2::types::fmi2Component,
            loggingOn: $crate::fmi2::types::fmi2Boolean,
            nCategories: usize,
            categories: *const $crate::fmi2::types::fmi2String,
        ) -> $crate::fmi2::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi2::functions::fmi2SetDebugLogging::<$model>(c, loggingOn, nCategories, categories) }
        }
        #[doc = concat!("`fmi2SetupExperiment` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2SetupExperiment(
            c: $crate::fmi2::types::fmi2Component,
            toleranceDefined: $crate::fmi2::types::fmi2Boolean,
            tolerance: $crate::fmi2::types::fmi2Real,
            startTime: $crate::fmi2::types::fmi2Real,
            stopTimeDefined: $crate::fmi2::types::fmi2Boolean,
            stopTime: $crate::fmi2::types::fmi2Real,
        ) -> $crate::fmi2::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi2::functions::fmi2SetupExperiment::<$model>(c, toleranceDefined, tolerance, startTime, stopTimeDefined, stopTime) }
        }
        #[doc = concat!("`fmi2EnterInitializationMode` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2EnterInitializationMode(
            c: $crate::fmi2::types::fmi2Component,
        ) -> $crate::fmi2::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi2::functions::fmi2EnterInitializationMode::<$model>(c) }
        }
        #[doc = concat!("`fmi2ExitInitializationMode` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2ExitInitializationMode(
            c: $crate::fmi2::types::fmi2Component,
        ) -> $crate::fmi2::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi2::functions::fmi2ExitInitializationMode::<$model>(c) }
        }
        #[doc = concat!("`fmi2Terminate` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2Terminate(
            c: $crate::fmi2::types::fmi2Component,
        ) -> $crate::fmi2::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi2::functions::fmi2Terminate::<$model>(c) }
        }
        #[doc = concat!("`fmi2Reset` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2Reset(
            c: $crate::fmi2::types::fmi2Component,
        ) -> $crate::fmi2::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi2::functions::fmi2Reset::<$model>(c) }
        }
        #[doc = concat!("`fmi2GetReal` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetReal(
            c: $crate::fmi2::types::fmi2Component,
            vr: *const $crate::fmi2::types::fmi2ValueReference,
            nvr: usize,
            value: *mut $crate::fmi2::types::fmi2Real,
        ) -> $crate::fmi2::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi2::functions::fmi2GetReal::<$model>(c, vr, nvr, value) }
        }
        #[doc = concat!("`fmi2GetInteger` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetInteger(
            c: $crate::fmi2::types::fmi2Component,
            vr: *const $crate::fmi2::types::fmi2ValueReference,
            nvr: usize,
            value: *mut $crate::fmi2::types::fmi2Integer,
        ) -> $crate::fmi2::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi2::functions::fmi2GetInteger::<$model>(c, vr, nvr, value) }
        }
        #[doc = concat!("`fmi2GetBoolean` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetBoolean(
            c: $crate::fmi2::types::fmi2Component,
            vr: *const $crate::fmi2::types::fmi2ValueReference,
            nvr: usize,
            value: *mut $crate::fmi2::types::fmi2Boolean,
        ) -> $crate::fmi2::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi2::functions::fmi2GetBoolean::<$model>(c, vr, nvr, value) }
        }
        #[doc = concat!("`fmi2GetString` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetString(
            c: $crate::fmi2::types::fmi2Component,
            vr: *const $crate::fmi2::types::fmi2ValueReference,
            nvr: usize,
            value: *mut $crate::fmi2::types::fmi2String,
        ) -> $crate::fmi2::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi2::functions::fmi2GetString::<$model>(c, vr, nvr, value) }
        }
        #[doc = concat!("`fmi2SetReal` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2SetReal(
            c: $crate::fmi2::types::fmi2Component,
            vr: *const $crate::fmi2::types::fmi2ValueReference,
            nvr: usize,
            value: *const $crate::fmi2::types::fmi2Real,
        ) -> $crate::fmi2::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi2::functions::fmi2SetReal::<$model>(c, vr, nvr, value) }
        }
        #[doc = concat!("`fmi2SetInteger` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2SetInteger(
            c: $crate::fmi2::types::fmi2Component,
            vr: *const $crate::fmi2::types::fmi2ValueReference,
            nvr: usize,
            value: *const $crate::fmi2::types::fmi2Integer,
        ) -> $crate::fmi2::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi2::functions::fmi2SetInteger::<$model>(c, vr, nvr, value) }
        }
        #[doc = concat!("`fmi2SetBoolean` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2SetBoolean(
            c: $crate::fmi2::types::fmi2Component,
            vr: *const $crate::fmi2::types::fmi2ValueReference,
            nvr: usize,
            value: *const $crate::fmi2::types::fmi2Boolean,
        ) -> $crate::fmi2::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi2::functions::fmi2SetBoolean::<$model>(c, vr, nvr, value) }
        }
        #[doc = concat!("`fmi2SetString` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2SetString(
            c: $crate::fmi2::types::fmi2Component,
            vr: *const $crate::fmi2::types::fmi2ValueReference,
            nvr: usize,
            value: *const $crate::fmi2::types::fmi2String,
        ) -> $crate::fmi2::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi2::functions::fmi2SetString::<$model>(c, vr, nvr, value) }
        }
        #[doc = concat!("`fmi2GetFMUstate` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetFMUstate(
            c: $crate::fmi2::types::fmi2Component,
            FMUstate: *mut $crate::fmi2::types::fmi2FMUstate,
        ) -> $crate::fmi2::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi2::functions::fmi2GetFMUstate::<$model>(c, FMUstate) }
        }
        #[doc = concat!("`fmi2SetFMUstate` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2SetFMUstate(
            c: $crate::fmi2::types::fmi2Component,
            FMUstate: $crate::fmi2::types::fmi2FMUstate,
        ) -> $crate::fmi2::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi2::functions::fmi2SetFMUstate::<$model>(c, FMUstate) }
        }
        #[doc = concat!("`fmi2FreeFMUstate` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2FreeFMUstate(
            c: $crate::fmi2::types::fmi2Component,
            FMUstate: *mut $crate::fmi2::types::fmi2FMUstate,
        ) -> $crate::fmi2::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi2::functions::fmi2FreeFMUstate::<$model>(c, FMUstate) }
        }
        #[doc = concat!("`fmi2SerializedFMUstateSize` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
            c: $crate::fmi2::types::fmi2Component,
            FMUstate: $crate::fmi2::types::fmi2FMUstate,
            size: *mut usize,
        ) -> $crate::fmi2::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi2::functions::fmi2SerializedFMUstateSize::<$model>(c, FMUstate, size) }
        }
        #[doc = concat!("`fmi2SerializeFMUstate` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2SerializeFMUstate(
            c: $crate::fmi2::types::fmi2Component,
            FMUstate: $crate::fmi2::types::fmi2FMUstate,
            serializedState: *mut $crate::fmi2::types::fmi2Byte,
            size: usize,
        ) -> $crate::fmi2::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi2::functions::fmi2SerializeFMUstate::<$model>(c, FMUstate, serializedState, size) }
        }
        #[doc = concat!("`fmi2DeSerializeFMUstate` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
            c: $crate::fmi2::types::fmi2Component,
            serializedState: *const $crate::fmi2::types::fmi2Byte,
            size: usize,
            FMUstate: *mut $crate::fmi2::types::fmi2FMUstate,
        ) -> $crate::fmi2::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi2::functions::fmi2DeSerializeFMUstate::<$model>(c, serializedState, size, FMUstate) }
        }
        #[doc = concat!("`fmi2GetDirectionalDerivative` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetDirectionalDerivative(
            c: $crate::fmi2::types::fmi2Component,
            vu: *const $crate::fmi2::types::fmi2ValueReference,
            nu: usize,
            vk: *const $crate::fmi2::types::fmi2ValueReference,
            nk: usize,
            dvk: *const $crate::fmi2::types::fmi2Real,
            dvu: *mut $crate::fmi2::types::fmi2Real,
        ) -> $crate::fmi2::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi2::functions::fmi2GetDirectionalDerivative::<$model>(c, vu, nu, vk, nk, dvk, dvu) }
        }
        #[doc = concat!("`fmi2SetRealInputDerivatives` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2SetRealInputDerivatives(
            c: $crate::fmi2::types::fmi2Component,
            vr: *const $crate::fmi2::types::fmi2ValueReference,
            nvr: usize,
            order: *const $crate::fmi2::types::fmi2Integer,
            value: *const $crate::fmi2::types::fmi2Real,
        ) -> $crate::fmi2::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi2::functions::fmi2SetRealInputDerivatives::<$model>(c, vr, nvr, order, value) }
        }
        #[doc = concat!("`fmi2GetRealOutputDerivatives` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetRealOutputDerivatives(
            c: $crate::fmi2::types::fmi2Component,
            vr: *const $crate::fmi2::types::fmi2ValueReference,
            nvr: usize,
            order: *const $crate::fmi2::types::fmi2Integer,
            value: *mut $crate::fmi2::types::fmi2Real,
        ) -> $crate::fmi2::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi2::functions::fmi2GetRealOutputDerivatives::<$model>(c, vr, nvr, order, value) }
        }
        #[doc = concat!("`fmi2DoStep` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2DoStep(
            c: $crate::fmi2::types::fmi2Component,
            currentCommunicationPoint: $crate::fmi2::types::fmi2Real,
            communicationStepSize: $crate::fmi2::types::fmi2Real,
            noSetFMUStatePriorToCurrentPoint: $crate::fmi2::types::fmi2Boolean,
        ) -> $crate::fmi2::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi2::functions::fmi2DoStep::<$model>(c, currentCommunicationPoint, communicationStepSize, noSetFMUStatePriorToCurrentPoint) }
        }
        #[doc = concat!("`fmi2CancelStep` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2CancelStep(
            c: $crate::fmi2::types::fmi2Component,
        ) -> $crate::fmi2::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi2::functions::fmi2CancelStep::<$model>(c) }
        }
        #[doc = concat!("`fmi2GetStatus` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetStatus(
            c: $crate::fmi2::types::fmi2Component,
            s: ::std::ffi::c_int,
            value: *mut ::std::ffi::c_int,
        ) -> $crate::fmi2::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi2::functions::fmi2GetStatus::<$model>(c, s, value) }
        }
        #[doc = concat!("`fmi2GetRealStatus` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetRealStatus(
            c: $crate::fmi2::types::fmi2Component,
            s: ::std::ffi::c_int,
            value: *mut $crate::fmi2::types::fmi2Real,
        ) -> $crate::fmi2::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi2::functions::fmi2GetRealStatus::<$model>(c, s, value) }
        }
        #[doc = concat!("`fmi2GetIntegerStatus` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetIntegerStatus(
            c: $crate::fmi2::types::fmi2Component,
            s: ::std::ffi::c_int,
            value: *mut $crate::fmi2::types::fmi2Integer,
        ) -> $crate::fmi2::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi2::functions::fmi2GetIntegerStatus::<$model>(c, s, value) }
        }
        #[doc = concat!("`fmi2GetBooleanStatus` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetBooleanStatus(
            c: $crate::fmi2::types::fmi2Component,
            s: ::std::ffi::c_int,
            value: *mut $crate::fmi2::types::fmi2Boolean,
        ) -> $crate::fmi2::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi2::functions::fmi2GetBooleanStatus::<$model>(c, s, value) }
        }
        #[doc = concat!("`fmi2GetStringStatus` (FMI 2.0) of `", stringify!($model), "`.")]
        #[doc = ""]
        #[doc = "# Safety"]
        #[doc = "The arguments follow the FMI 2.0 standard (live instance or null, arrays of the given length)."]
        #[no_mangle]
        pub unsafe extern "C" fn fmi2GetStringStatus(
            c: $crate::fmi2::types::fmi2Component,
            s: ::std::ffi::c_int,
            value: *mut $crate::fmi2::types::fmi2String,
        ) -> $crate::fmi2::types::fmi2Status {
            // SAFETY: the caller's contract is the generic function's.
            unsafe { $crate::fmi2::functions::fmi2GetStringStatus::<$model>(c, s, value) }
        }
    };
}
