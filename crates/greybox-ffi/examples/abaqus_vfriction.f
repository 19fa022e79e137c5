C     greybox friction law in Abaqus/Explicit general contact through VFRICTION
C     (*FRICTION, USER=FRICTION). Per contact point: p = fNormal/areaCont,
C     v = |dSlipFric|/dt, T = (tempSlv + tempMst)/2; the tangential force is
C     -min(mu*fNormal, fStickForce) along the slip direction (Coulomb with stick limit).
C     The law is loaded once in VEXTERNALDB (LOP=0) from $GREYBOX_LAW. PROPS as in
C     abaqus_fric_coef.f. Build notes: crates/greybox-ffi/README.md.
      module greybox_vabaqus
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
        function gb_mu(h, n, p, v, t, mu) bind(C, name='greybox_law_mu')
     &      result(status)
          import :: c_ptr, c_size_t, c_double, c_int32_t
          type(c_ptr), value :: h
          integer(c_size_t), value :: n
          real(c_double), dimension(*), intent(in) :: p, v, t
          real(c_double), dimension(*), intent(out) :: mu
          integer(c_int32_t) :: status
        end function
      end interface
      end module greybox_vabaqus

      subroutine vexternaldb(lOp, i_Array, niArray, r_Array, nrArray)
      use greybox_vabaqus
      include 'vaba_param.inc'
      dimension i_Array(niArray), r_Array(nrArray)
      character(len=1024) path
      if (lOp .eq. 0) then
        call get_environment_variable('GREYBOX_LAW', path)
        if (gb_load(trim(path)//c_null_char, law) .ne. 0) then
          write (*, *) 'greybox: cannot load the law ', trim(path)
          call xplb_exit
        end if
      end if
      return
      end

      subroutine vfriction(fTangential, state, nBlock, nBlockAnal,
     &   nBlockEdge, nNodState, nNodSlv, nNodMst, nFricDir, nDir,
     &   nStates, nProps, nTemp, nFields, jFlags, rData, surfInt,
     &   surfSlv, surfMst, jConSlvUid, jConMstUid, props, dSlipFric,
     &   fStickForce, fTangPrev, fNormal, areaCont, dircosN, dircosSl,
     &   shapeSlv, shapeMst, coordSlv, coordMst, velSlv, velMst,
     &   tempSlv, tempMst, fieldSlv, fieldMst)
      use greybox_vabaqus
      include 'vaba_param.inc'
      dimension fTangential(nFricDir,nBlock),
     &   state(nStates,nNodState,nBlock),
     &   jConSlvUid(nNodSlv,nBlock), jConMstUid(nNodMst,nBlockAnal),
     &   props(nProps), dSlipFric(nDir,nBlock), fStickForce(nBlock),
     &   fTangPrev(nDir,nBlock), fNormal(nBlock), areaCont(nBlock),
     &   dircosN(nDir,nBlock), dircosSl(nDir,nBlock),
     &   shapeSlv(nNodSlv,nBlockEdge), shapeMst(nNodMst,nBlockAnal),
     &   coordSlv(nDir,nNodSlv,nBlock), coordMst(nDir,nNodMst,nBlockAnal),
     &   velSlv(nDir,nNodSlv,nBlock), velMst(nDir,nNodMst,nBlockAnal),
     &   tempSlv(nBlock), tempMst(nBlockAnal),
     &   fieldSlv(nFields,nBlock), fieldMst(nFields,nBlockAnal)
      parameter (iKStep=1, iKInc=2, iLConType=3, nFlags=3)
      parameter (iTimStep=1, iTimGlb=2, iDTimCur=3, iFrictionWork=4,
     &   nData=4)
      dimension jFlags(nFlags), rData(nData)
      character*80 surfInt, surfSlv, surfMst
      parameter (maxb = 512)
      real(c_double) p(maxb), v(maxb), t(maxb), mu(maxb)
      integer(c_size_t) nb
      dtc = max(rData(iDTimCur), 1.d-30)
      do k0 = 0, nBlock - 1, maxb
        nb = min(maxb, nBlock - k0)
        do k = 1, int(nb)
          kb = k0 + k
          p(k) = max(fNormal(kb), 0.d0) / max(areaCont(kb), 1.d-30)
     &           * props(1)
          slip = 0.d0
          do i = 1, nDir
            slip = slip + dSlipFric(i, kb)**2
          end do
          v(k) = sqrt(slip) / dtc * props(2)
          kb2 = min(kb, nBlockAnal)
          if (nTemp .gt. 0) then
            t(k) = 0.5d0 * (tempSlv(kb) + tempMst(kb2)) + props(3)
          else
            t(k) = 293.15d0
          end if
        end do
        if (gb_mu(law, nb, p, v, t, mu) .ne. 0) then
          write (*, *) 'greybox: evaluation failed'
          call xplb_exit
        end if
        do k = 1, int(nb)
          kb = k0 + k
          fTangential(1, kb) = -min(mu(k) * fNormal(kb), fStickForce(kb))
          do i = 2, nFricDir
            fTangential(i, kb) = 0.d0
          end do
        end do
      end do
      return
      end
