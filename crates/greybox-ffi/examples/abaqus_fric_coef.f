C     greybox friction law in Abaqus/Standard through FRIC_COEF (*FRICTION, USER=COEFFICIENT).
C     The law is loaded once in UEXTERNALDB (LOP=0) from the file named by the environment
C     variable GREYBOX_LAW and evaluated for the whole block in one batch call.
C     PROPS(1) = Pa per model pressure unit (1.0D6 for MPa), PROPS(2) = m/s per model slip-rate
C     unit (1.0D-3 for mm/s), PROPS(3) = K offset of the model temperature (273.15 for C).
C     Build: see crates/greybox-ffi/README.md (link libgreybox_ffi).
      module greybox_abaqus
      use, intrinsic :: iso_c_binding
      implicit none
      type(c_ptr), save :: law = c_null_ptr
      interface
        function gb_load(path, out) bind(C, name='greybox_law_load')
     &      result(status)
          import :: c_char, c_ptr, c_int32_t
          character(kind=c_char), dimension(*), intent(in) :: path
          type(c_ptr), intent(out) :: out
          integer(c_int32_t) :: status
        end function
        function gb_mu_grad(h, n, p, v, t, mu, dp, dv, dt)
     &      bind(C, name='greybox_law_mu_grad') result(status)
          import :: c_ptr, c_size_t, c_double, c_int32_t
          type(c_ptr), value :: h
          integer(c_size_t), value :: n
          real(c_double), dimension(*), intent(in) :: p, v, t
          real(c_double), dimension(*), intent(out) :: mu, dp, dv, dt
          integer(c_int32_t) :: status
        end function
      end interface
      end module greybox_abaqus

      subroutine uexternaldb(lop, lrestart, time, dtime, kstep, kinc)
      use greybox_abaqus
      include 'aba_param.inc'
      dimension time(2)
      character(len=1024) path
      if (lop .eq. 0 .or. lop .eq. 4) then
        call get_environment_variable('GREYBOX_LAW', path)
        if (gb_load(trim(path)//c_null_char, law) .ne. 0) then
          write (7, *) 'greybox: cannot load the law ', trim(path)
          call xit
        end if
      end if
      return
      end

      subroutine fric_coef(fCoef, fCoefDeriv, nBlock, nProps, nTemp,
     &   nFields, iData, rData, surfInt, surfSec, surfMain, props,
     &   slipData, pressure, tempAvg, fieldAvg)
      use greybox_abaqus
      include 'aba_param.inc'
      dimension fCoef(nBlock,2), fCoefDeriv(nBlock,20,2),
     &   props(nProps), slipData(nBlock,6), pressure(nBlock),
     &   tempAvg(nBlock), fieldAvg(nBlock,nFields)
      dimension iData(*), rData(*)
      character*80 surfInt, surfSec, surfMain
      parameter (maxb = 512)
      real(c_double) p(maxb), v(maxb), t(maxb), mu(maxb)
      real(c_double) dp(maxb), dv(maxb), dt(maxb)
      integer(c_size_t) nb
      do k0 = 0, nBlock - 1, maxb
        nb = min(maxb, nBlock - k0)
        do k = 1, int(nb)
          p(k) = max(pressure(k0 + k), 0.d0) * props(1)
          v(k) = slipData(k0 + k, 1) * props(2)
          if (nTemp .gt. 0) then
            t(k) = tempAvg(k0 + k) + props(3)
          else
            t(k) = 293.15d0
          end if
        end do
        if (gb_mu_grad(law, nb, p, v, t, mu, dp, dv, dt) .ne. 0) then
          write (7, *) 'greybox: evaluation failed'
          call xit
        end if
        do k = 1, int(nb)
          fCoef(k0 + k, 1) = mu(k)
          fCoefDeriv(k0 + k, 1, 1) = dv(k) * props(2)
          fCoefDeriv(k0 + k, 2, 1) = dp(k) * props(1)
          fCoefDeriv(k0 + k, 3, 1) = dt(k)
        end do
      end do
      return
      end
