//! The evaluation path of the C ABI does not allocate: a counting global allocator sees zero
//! allocations across thousands of batch calls (learned grey-box laws and the models' exact or
//! adaptive surrogate tables).

mod common;
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

struct Counting;
static ALLOCS: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCS.fetch_add(1, Ordering::SeqCst);
        // SAFETY: forwarded to the system allocator with the caller's layout.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: forwarded to the system allocator.
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn batch_evaluation_does_not_allocate() {
    let dir = tempfile::tempdir().unwrap();
    // a smooth learned model inside a grey-box law
    for family in [
        greybox_model::Family::Mlp,
        greybox_model::Family::GradientBoosting,
        greybox_model::Family::Svr,
    ] {
        let model = common::small_model(family, greybox_model::mlp::Activation::Relu);
        model.save(&dir.path().join("m.json")).unwrap();
        std::fs::write(dir.path().join("law.json"), r#"{"law": "grey-box", "inner": {"law": "learned", "model": "m.json"}, "outside": {"law": "power-fit"}, "shear_cap_k_MPa": 600, "clamp": [0.05, 1.0]}"#).unwrap();
        // and the model's surrogate table (exact for the trees, adaptive otherwise)
        let learned = greybox_friction::spec::load_law(&dir.path().join("m.json")).unwrap();
        let domain = learned.domain().unwrap();
        let mut o = greybox_friction::surrogate::SurrogateOptions::over_domain(&domain);
        o.check_points = 2000;
        let table = greybox_friction::surrogate::build(learned.as_ref(), &o).unwrap();
        std::fs::write(dir.path().join("table.json"), table.to_json().unwrap()).unwrap();
        for file in ["law.json", "table.json"] {
            evaluate_without_allocating(&dir.path().join(file), family);
        }
    }
}

/// Load `file` through the C ABI and count allocations across batch calls.
fn evaluate_without_allocating(file: &std::path::Path, family: greybox_model::Family) {
    {
        let path = std::ffi::CString::new(file.to_str().unwrap()).unwrap();
        let mut law = std::ptr::null_mut();
        // SAFETY: valid C string and out pointer.
        assert_eq!(
            unsafe { greybox_ffi::greybox_law_load(path.as_ptr(), &mut law) },
            greybox_ffi::GREYBOX_OK
        );
        let n = 256;
        let p: Vec<f64> = (0..n).map(|i| 5e8 + 1e7 * i as f64).collect();
        let v: Vec<f64> = (0..n).map(|i| 0.1 + 0.02 * i as f64).collect();
        let t = vec![300.0; n];
        let (mut mu, mut dp, mut dv, mut dt) =
            (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        let before = ALLOCS.load(Ordering::SeqCst);
        for _ in 0..200 {
            // SAFETY: arrays of n values, live handle.
            let rc = unsafe {
                greybox_ffi::greybox_law_mu(
                    law,
                    n,
                    p.as_ptr(),
                    v.as_ptr(),
                    t.as_ptr(),
                    mu.as_mut_ptr(),
                )
            };
            assert_eq!(rc, greybox_ffi::GREYBOX_OK);
            // SAFETY: as above.
            let rc = unsafe {
                greybox_ffi::greybox_law_mu_grad(
                    law,
                    n,
                    p.as_ptr(),
                    v.as_ptr(),
                    t.as_ptr(),
                    mu.as_mut_ptr(),
                    dp.as_mut_ptr(),
                    dv.as_mut_ptr(),
                    dt.as_mut_ptr(),
                )
            };
            assert_eq!(rc, greybox_ffi::GREYBOX_OK);
        }
        let after = ALLOCS.load(Ordering::SeqCst);
        assert_eq!(
            after - before,
            0,
            "{family:?} {}: {} allocations on the evaluation path",
            file.display(),
            after - before
        );
        // SAFETY: handle from greybox_law_load, freed once.
        unsafe { greybox_ffi::greybox_law_free(law) };
    }
}
