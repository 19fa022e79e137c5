! Evaluates a law from Fortran at three points; prints mu with 17 decimals (exact round trip).
program test_fortran
  use greybox
  use, intrinsic :: iso_c_binding
  implicit none
  type(c_ptr) :: law
  character(len=1024) :: path
  real(c_double) :: p(3), v(3), t(3), mu(3), dp(3), dv(3), dt(3)
  integer :: i
  call get_command_argument(1, path)
  if (greybox_load(path, law) /= GREYBOX_OK) then
    print *, 'load failed: ', trim(greybox_error_message())
    stop 1
  end if
  p = [1.0d9, 1.5d9, 2.0d9]
  v = [0.5d0, 1.5d0, 3.5d0]
  t = [293.15d0, 293.15d0, 293.15d0]
  if (greybox_law_mu(law, 3_c_size_t, p, v, t, mu) /= GREYBOX_OK) stop 1
  do i = 1, 3
    write (*, '(A,ES26.17E3)') 'mu ', mu(i)
  end do
  if (greybox_law_mu_grad(law, 3_c_size_t, p, v, t, mu, dp, dv, dt) /= GREYBOX_OK) stop 1
  p(1) = -1.0d0
  if (greybox_law_mu(law, 1_c_size_t, p, v, t, mu) /= GREYBOX_ERR_INPUT) stop 1
  print '(A,A)', 'error ', trim(greybox_error_message())
  ! the checked wrappers pass each array's size: a short one is refused, not read past
  p(1) = 1.0d9
  if (greybox_mu(law, p, v(1:2), t, mu) /= GREYBOX_ERR_LENGTH) stop 1
  print '(A,A)', 'length ', trim(greybox_error_message())
  if (greybox_mu_grad(law, p, v, t, mu, dp, dv, dt(1:1)) /= GREYBOX_ERR_LENGTH) stop 1
  if (greybox_mu(law, p, v, t, mu) /= GREYBOX_OK) stop 1
  do i = 1, 3
    write (*, '(A,ES26.17E3)') 'checked ', mu(i)
  end do
  call greybox_law_free(law)
end program
