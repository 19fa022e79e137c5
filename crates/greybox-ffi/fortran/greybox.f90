! greybox Fortran module: iso_c_binding interfaces to the greybox C ABI (include/greybox.h).
! Units: pressure Pa, sliding velocity m/s, temperature K. Status 0 = GREYBOX_OK.
module greybox
  use, intrinsic :: iso_c_binding
  implicit none
  private
  public :: greybox_law_load, greybox_law_free, greybox_law_mu, greybox_law_mu_grad, &
            greybox_last_error, greybox_load, greybox_error_message, &
            GREYBOX_OK, GREYBOX_ERR_NULL, GREYBOX_ERR_LOAD, GREYBOX_ERR_INPUT, GREYBOX_ERR_PANIC

  integer(c_int32_t), parameter :: GREYBOX_OK = 0, GREYBOX_ERR_NULL = 1, GREYBOX_ERR_LOAD = 2, &
                                   GREYBOX_ERR_INPUT = 3, GREYBOX_ERR_PANIC = 4

  interface
    function greybox_law_load(path, law) bind(C, name="greybox_law_load") result(status)
      import :: c_char, c_ptr, c_int32_t
      character(kind=c_char), dimension(*), intent(in) :: path
      type(c_ptr), intent(out) :: law
      integer(c_int32_t) :: status
    end function

    subroutine greybox_law_free(law) bind(C, name="greybox_law_free")
      import :: c_ptr
      type(c_ptr), value :: law
    end subroutine

    function greybox_law_mu(law, n, pressure_pa, velocity_m_s, temperature_k, mu) &
        bind(C, name="greybox_law_mu") result(status)
      import :: c_ptr, c_size_t, c_double, c_int32_t
      type(c_ptr), value :: law
      integer(c_size_t), value :: n
      real(c_double), dimension(*), intent(in) :: pressure_pa, velocity_m_s, temperature_k
      real(c_double), dimension(*), intent(out) :: mu
      integer(c_int32_t) :: status
    end function

    function greybox_law_mu_grad(law, n, pressure_pa, velocity_m_s, temperature_k, mu, &
        dmu_dp, dmu_dv, dmu_dt) bind(C, name="greybox_law_mu_grad") result(status)
      import :: c_ptr, c_size_t, c_double, c_int32_t
      type(c_ptr), value :: law
      integer(c_size_t), value :: n
      real(c_double), dimension(*), intent(in) :: pressure_pa, velocity_m_s, temperature_k
      real(c_double), dimension(*), intent(out) :: mu, dmu_dp, dmu_dv, dmu_dt
      integer(c_int32_t) :: status
    end function

    function greybox_last_error(buf, len) bind(C, name="greybox_last_error") result(n)
      import :: c_char, c_size_t
      character(kind=c_char), dimension(*), intent(out) :: buf
      integer(c_size_t), value :: len
      integer(c_size_t) :: n
    end function
  end interface

contains

  ! Load a law from a Fortran string (trailing blanks ignored).
  function greybox_load(path, law) result(status)
    character(len=*), intent(in) :: path
    type(c_ptr), intent(out) :: law
    integer(c_int32_t) :: status
    status = greybox_law_load(trim(path) // c_null_char, law)
  end function

  ! The calling thread's last error message as a Fortran string.
  function greybox_error_message() result(msg)
    character(len=512) :: msg
    character(kind=c_char) :: buf(512)
    integer(c_size_t) :: n
    integer :: i
    n = greybox_last_error(buf, int(size(buf), c_size_t))
    msg = ' '
    do i = 1, min(int(n), 511)
      msg(i:i) = buf(i)
    end do
  end function

end module greybox
