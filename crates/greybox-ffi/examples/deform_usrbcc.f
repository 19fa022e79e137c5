C     greybox friction law in DEFORM-2D through the user boundary-condition routine USRBCC
C     (FRCFAC/FRCWIN with FricDefType = -n selects user routine n; IMODE = 1, ITYPE = 2 asks
C     for the friction coefficient in VARIABLE). USRUPD stores each contact node's normal
C     pressure PRESR(2) (MPa) and sliding velocity SLDVEL (mm/s) in user node variables 1 and
C     2; USRBCC averages them over the edge NODE1-NODE2 and evaluates the law. DEFORM computes
C     PRESR and SLDVEL only for elastic (not rigid) dies. The law file is named by $GREYBOX_LAW.
C     Signatures from the public DEFORM-2D v12 routines; check them against your version.
      module greybox_deform
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
      contains
        subroutine ensure_loaded()
          character(len=1024) path
          if (.not. c_associated(law)) then
            call get_environment_variable('GREYBOX_LAW', path)
            if (gb_load(trim(path)//c_null_char, law) .ne. 0) then
              write (*, *) 'greybox: cannot load the law ', trim(path)
              stop 1
            end if
          end if
        end subroutine
      end module greybox_deform

      SUBROUTINE USRBCC(VARIABLE,NODE1,NODE2,IELEM,NBCD,NDIE,RZ,DRZ,
     &                  USRNOD,NUSRN,ENVTEM,TEMO,TEMC,CURTIM,MODEL,
     &                  IMODE,ITYPE,NURZ)
      use greybox_deform
      IMPLICIT DOUBLE PRECISION (A-H,O-Z)
      DIMENSION RZ(NURZ,*),DRZ(NURZ,*),USRNOD(NUSRN,*),TEMO(*),TEMC(*)
      real(c_double) p(1), v(1), t(1), mu(1)
      IF (IMODE .NE. 1 .OR. ITYPE .NE. 2 .OR. NDIE .EQ. 0) RETURN
      call ensure_loaded()
C     MPa -> Pa, mm/s -> m/s, C -> K
      p(1) = 0.5D0 * (USRNOD(1,NODE1) + USRNOD(1,NODE2)) * 1.0D6
      v(1) = 0.5D0 * (USRNOD(2,NODE1) + USRNOD(2,NODE2)) * 1.0D-3
      t(1) = 0.5D0 * (TEMC(NODE1) + TEMC(NODE2)) + 273.15D0
      IF (gb_mu(law, 1_c_size_t, p, v, t, mu) .NE. 0) STOP 1
      VARIABLE = mu(1)
      RETURN
      END
