! greybox Fortran module: iso_c_binding interfaces to the greybox C ABI (include/greybox.h).
! Units: pressure Pa, sliding velocity m/s, temperature K. Status 0 = GREYBOX_OK.
module greybox
  use, intrinsic :: iso_c_binding
  implicit none
  private
  public :: greybox_law_load, greybox_law_free, greybox_law_mu, greybox_law_mu_grad, &
            greybox_law_eval, greybox_last_error, greybox_load, greybox_error_message, &
            greybox_mu, greybox_mu_grad, &
            GREYBOX_OK, GREYBOX_ERR_NULL, GREYBOX_ERR_LOAD, GREYBOX_ERR_INPUT, GREYBOX_ERR_PANIC, &
            GREYBOX_ERR_LENGTH, GREYBOX_ERR_MU

  integer(c_int32_t), parameter :: GREYBOX_OK = 0, GREYBOX_ERR_NULL = 1, GREYBOX_ERR_LOAD = 2, &
                                   GREYBOX_ERR_INPUT = 3, GREYBOX_ERR_PANIC = 4, &
                                   GREYBOX_ERR_LENGTH = 5, GREYBOX_ERR_MU = 6

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

    ! Every array with its length (values it holds), as C pointers (c_loc of a contiguous
    ! array, or c_null_ptr for an output not wanted and for temperature_k at room
    ! temperature): an array shorter than n is refused (GREYBOX_ERR_LENGTH) before anything
    ! is read or written. greybox_mu / greybox_mu_grad below pass size() of each array.
    function greybox_law_eval(law, n, pressure_pa, pressure_len, velocity_m_s, velocity_len, &
        temperature_k, temperature_len, mu, mu_len, dmu_dp, dmu_dp_len, dmu_dv, dmu_dv_len, &
        dmu_dt, dmu_dt_len) bind(C, name="greybox_law_eval") result(status)
      import :: c_ptr, c_size_t, c_int32_t
      type(c_ptr), value :: law, pressure_pa, velocity_m_s, temperature_k, mu, dmu_dp, dmu_dv, dmu_dt
      integer(c_size_t), value :: n, pressure_len, velocity_len, temperature_len, mu_len, &
                                  dmu_dp_len, dmu_dv_len, dmu_dt_len
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

  ! mu for the states (pressure_pa(i), velocity_m_s(i), temperature_k(i)), i = 1..n, where n
  ! is size(pressure_pa); every array's own size is passed and checked (GREYBOX_ERR_LENGTH
  ! for an array shorter than pressure_pa), so no count can read or write past an array.
  function greybox_mu(law, pressure_pa, velocity_m_s, temperature_k, mu) result(status)
    type(c_ptr), intent(in) :: law
    real(c_double), intent(in), contiguous, target :: pressure_pa(:), velocity_m_s(:), temperature_k(:)
    real(c_double), intent(inout), contiguous, target :: mu(:)
    integer(c_int32_t) :: status
    status = greybox_law_eval(law, int(size(pressure_pa), c_size_t), &
        c_loc(pressure_pa), int(size(pressure_pa), c_size_t), &
        c_loc(velocity_m_s), int(size(velocity_m_s), c_size_t), &
        c_loc(temperature_k), int(size(temperature_k), c_size_t), &
        c_loc(mu), int(size(mu), c_size_t), &
        c_null_ptr, 0_c_size_t, c_null_ptr, 0_c_size_t, c_null_ptr, 0_c_size_t)
  end function

  ! greybox_mu with the derivatives dmu_dp [1/Pa], dmu_dv [s/m], dmu_dt [1/K].
  function greybox_mu_grad(law, pressure_pa, velocity_m_s, temperature_k, mu, dmu_dp, dmu_dv, &
      dmu_dt) result(status)
    type(c_ptr), intent(in) :: law
    real(c_double), intent(in), contiguous, target :: pressure_pa(:), velocity_m_s(:), temperature_k(:)
    real(c_double), intent(inout), contiguous, target :: mu(:), dmu_dp(:), dmu_dv(:), dmu_dt(:)
    integer(c_int32_t) :: status
    status = greybox_law_eval(law, int(size(pressure_pa), c_size_t), &
        c_loc(pressure_pa), int(size(pressure_pa), c_size_t), &
        c_loc(velocity_m_s), int(size(velocity_m_s), c_size_t), &
        c_loc(temperature_k), int(size(temperature_k), c_size_t), &
        c_loc(mu), int(size(mu), c_size_t), c_loc(dmu_dp), int(size(dmu_dp), c_size_t), &
        c_loc(dmu_dv), int(size(dmu_dv), c_size_t), c_loc(dmu_dt), int(size(dmu_dt), c_size_t))
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
