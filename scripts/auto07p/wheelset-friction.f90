!----------------------------------------------------------------------
! AUTO-07p right-hand side of critspeed's wheelset (MODEL.md) with the friction coefficient as
! the second parameter PAR(3), for the generalised Hopf (Bautin) cross-check run by
! scripts/auto07p-curve; otherwise scripts/auto07p/wheelset.f90 (scripts/auto07p-compare), with
! the state unit SC from scale.inc: knife-edge rails under a wheel whose rolling radius is the odd
! cubic r_R(y) = r0 + LAM*y + KAP*y**3 (KAP = 0: the cone of seed-hunting-cone), roll
! phi = (r_R - r_L)/(2 l0), contact angles delta_R,L = LAM +- phi, Shen-Hedrick-Elkins creep
! with spin, no flange. The same functions critspeed evaluates for studies/seed-hunting-cone
! (closed-form cone) and studies/cubic-fold.toml (the cubic, through its table, which
! reproduces cubics exactly). KAP comes from geometry.inc, written per case by the script.
! Adapted from scripts/auto07p/wheelset.f90 (the cone case).
! State in units of SC (m, rad): U(1) = y/SC, U(2) = psi/SC, U(3) = ydot/(OMS SC),
! U(4) = psidot/(OMS SC), OMS = 30 rad/s; PAR(1) = V [m/s]; PAR(2) = max U(1) (PVLS);
! PAR(3) = friction coefficient mu [-]; PAR(11) = period [s]. AUTO's first Lyapunov coefficient
! (its GH test function) comes from finite differences of this right-hand side whose steps are
! set in these units: SC = 1 mm (scripts/auto07p/wheelset.f90's unit) leaves only rounding noise,
! and the GH points move with SC like SC^2 (truncation); scripts/auto07p-curve runs several.
! Derivatives (JAC = 1, the fold-of-cycles continuation c.lp): FUNC also returns DFDU and
! DFDP(:,1:3) by complex-step differentiation, d f/d x = Im f(x + i h)/h with h = 1d-30, exact to
! rounding: GEOMC, SIDEC and FUNCC are GEOM, SIDE and FUNC's arithmetic in complex numbers and
! must be kept identical to them. FUNC's real path (F alone: JAC = 0, IJAC = 0, the c.hb and c.gh
! runs) does not use them.
!----------------------------------------------------------------------
SUBROUTINE GEOM(Y, D)
  ! D = r_R(y) - r0 = r0 - r_L(y) (m)
  IMPLICIT NONE
  DOUBLE PRECISION, INTENT(IN) :: Y
  DOUBLE PRECISION, INTENT(OUT) :: D
  DOUBLE PRECISION, PARAMETER :: LAM=0.15d0
  INCLUDE 'geometry.inc'
  D = LAM*Y + KAP*Y*Y*Y
END SUBROUTINE GEOM

SUBROUTINE SIDE(SG, Y, PSI, YD, PSID, V, MU, FX, FY, MZ)
  IMPLICIT NONE
  DOUBLE PRECISION, INTENT(IN) :: SG, Y, PSI, YD, PSID, V, MU
  DOUBLE PRECISION, INTENT(OUT) :: FX, FY, MZ
  DOUBLE PRECISION, PARAMETER :: W=110000d0, L0=0.7429d0, R0=0.46d0, LAM=0.15d0
  DOUBLE PRECISION, PARAMETER :: F11=8.06d6, F22=8.09d6, F23=2.2d4, F33=12.7d0
  DOUBLE PRECISION :: D, PHI, R, DL, XN, XIX, XIY, OM, BETA, EPS
  CALL GEOM(Y, D)
  PHI = D/L0
  R = R0 + SG*D
  DL = LAM + SG*PHI
  XN = 0.5d0*W/COS(DL)
  XIX = 1d0 - R/R0 - SG*L0*PSID/V
  XIY = YD/V - PSI
  OM = PSID/V - SG*SIN(DL)/R0
  FX = -F11*XIX
  FY = -F22*XIY - F23*OM
  MZ = F23*XIY - F33*OM
  BETA = SQRT(FX*FX + FY*FY)/(MU*XN)
  IF (BETA < 3d0) THEN
     EPS = 1d0 - BETA/3d0 + BETA*BETA/27d0
  ELSE
     EPS = 1d0/BETA
  END IF
  FX = EPS*FX; FY = EPS*FY; MZ = EPS*MZ
END SUBROUTINE SIDE

SUBROUTINE FUNC(NDIM,U,ICP,PAR,IJAC,F,DFDU,DFDP)
  IMPLICIT NONE
  INTEGER, INTENT(IN) :: NDIM, ICP(*), IJAC
  DOUBLE PRECISION, INTENT(IN) :: U(NDIM), PAR(*)
  DOUBLE PRECISION, INTENT(OUT) :: F(NDIM)
  DOUBLE PRECISION, INTENT(INOUT) :: DFDU(NDIM,NDIM), DFDP(NDIM,*)
  DOUBLE PRECISION, PARAMETER :: XM=1250d0, XIZ=700d0, W=110000d0, L0=0.7429d0, LAM=0.15d0
  DOUBLE PRECISION, PARAMETER :: KPY=3d5, KPX=8.5d5, CPY=8d3, CPX=1d5, HS=0.9d0, OMS=30d0
  DOUBLE PRECISION :: Y, PSI, YD, PSID, V, FXR, FYR, MZR, FXL, FYL, MZL, FN, FS, MS, PHI, D
  INCLUDE 'scale.inc'
  Y = SC*U(1); PSI = SC*U(2); YD = SC*OMS*U(3); PSID = SC*OMS*U(4); V = PAR(1)
  CALL SIDE( 1d0, Y, PSI, YD, PSID, V, PAR(3), FXR, FYR, MZR)
  CALL SIDE(-1d0, Y, PSI, YD, PSID, V, PAR(3), FXL, FYL, MZL)
  CALL GEOM(Y, D)
  PHI = D/L0
  ! gravitational stiffness -W/2 (tan delta_R - tan delta_L)
  FN = -0.5d0*W*(TAN(LAM + PHI) - TAN(LAM - PHI))
  FS = -2d0*KPY*Y - 2d0*CPY*YD
  MS = -2d0*KPX*HS*HS*PSI - 2d0*CPX*HS*HS*PSID
  F(1) = OMS*U(3)
  F(2) = OMS*U(4)
  F(3) = (FYR + FYL + FN + FS)/(XM*OMS*SC)
  F(4) = (L0*(FXL - FXR) + MZR + MZL + MS)/(XIZ*OMS*SC)
  IF (IJAC == 0) RETURN
  CALL DERIVS(NDIM, U, PAR, IJAC, DFDU, DFDP)
END SUBROUTINE FUNC

SUBROUTINE DERIVS(NDIM, U, PAR, IJAC, DFDU, DFDP)
  ! complex step: DFDU(:,J) = Im F(U + i H e_J)/H; IJAC = 2 also DFDP(:,1:3) (V, PAR(2), mu)
  IMPLICIT NONE
  INTEGER, INTENT(IN) :: NDIM, IJAC
  DOUBLE PRECISION, INTENT(IN) :: U(NDIM), PAR(*)
  DOUBLE PRECISION, INTENT(INOUT) :: DFDU(NDIM,NDIM), DFDP(NDIM,*)
  DOUBLE PRECISION, PARAMETER :: H=1d-30
  COMPLEX(KIND(1d0)) :: UC(4), FC(4), VC, MUC
  INTEGER :: J
  DO J = 1, NDIM
     UC = CMPLX(U(1:4), 0d0, KIND(1d0))
     UC(J) = CMPLX(U(J), H, KIND(1d0))
     CALL FUNCC(UC, CMPLX(PAR(1), 0d0, KIND(1d0)), CMPLX(PAR(3), 0d0, KIND(1d0)), FC)
     DFDU(:,J) = AIMAG(FC)/H
  END DO
  IF (IJAC < 2) RETURN
  UC = CMPLX(U(1:4), 0d0, KIND(1d0))
  VC = CMPLX(PAR(1), H, KIND(1d0))
  MUC = CMPLX(PAR(3), 0d0, KIND(1d0))
  CALL FUNCC(UC, VC, MUC, FC)
  DFDP(1:4,1) = AIMAG(FC)/H
  DFDP(1:4,2) = 0d0
  VC = CMPLX(PAR(1), 0d0, KIND(1d0))
  MUC = CMPLX(PAR(3), H, KIND(1d0))
  CALL FUNCC(UC, VC, MUC, FC)
  DFDP(1:4,3) = AIMAG(FC)/H
END SUBROUTINE DERIVS

SUBROUTINE GEOMC(Y, D)
  ! GEOM in complex arithmetic
  IMPLICIT NONE
  COMPLEX(KIND(1d0)), INTENT(IN) :: Y
  COMPLEX(KIND(1d0)), INTENT(OUT) :: D
  DOUBLE PRECISION, PARAMETER :: LAM=0.15d0
  INCLUDE 'geometry.inc'
  D = LAM*Y + KAP*Y*Y*Y
END SUBROUTINE GEOMC

SUBROUTINE SIDEC(SG, Y, PSI, YD, PSID, V, MU, FX, FY, MZ)
  ! SIDE in complex arithmetic (the creep-saturation branch chosen on the real part)
  IMPLICIT NONE
  DOUBLE PRECISION, INTENT(IN) :: SG
  COMPLEX(KIND(1d0)), INTENT(IN) :: Y, PSI, YD, PSID, V, MU
  COMPLEX(KIND(1d0)), INTENT(OUT) :: FX, FY, MZ
  DOUBLE PRECISION, PARAMETER :: W=110000d0, L0=0.7429d0, R0=0.46d0, LAM=0.15d0
  DOUBLE PRECISION, PARAMETER :: F11=8.06d6, F22=8.09d6, F23=2.2d4, F33=12.7d0
  COMPLEX(KIND(1d0)) :: D, PHI, R, DL, XN, XIX, XIY, OM, BETA, EPS
  CALL GEOMC(Y, D)
  PHI = D/L0
  R = R0 + SG*D
  DL = LAM + SG*PHI
  XN = 0.5d0*W/COS(DL)
  XIX = 1d0 - R/R0 - SG*L0*PSID/V
  XIY = YD/V - PSI
  OM = PSID/V - SG*SIN(DL)/R0
  FX = -F11*XIX
  FY = -F22*XIY - F23*OM
  MZ = F23*XIY - F33*OM
  BETA = SQRT(FX*FX + FY*FY)/(MU*XN)
  IF (REAL(BETA) < 3d0) THEN
     EPS = 1d0 - BETA/3d0 + BETA*BETA/27d0
  ELSE
     EPS = 1d0/BETA
  END IF
  FX = EPS*FX; FY = EPS*FY; MZ = EPS*MZ
END SUBROUTINE SIDEC

SUBROUTINE FUNCC(U, V, MU, F)
  ! FUNC's right-hand side in complex arithmetic (U, V = PAR(1), MU = PAR(3))
  IMPLICIT NONE
  COMPLEX(KIND(1d0)), INTENT(IN) :: U(4), V, MU
  COMPLEX(KIND(1d0)), INTENT(OUT) :: F(4)
  DOUBLE PRECISION, PARAMETER :: XM=1250d0, XIZ=700d0, W=110000d0, L0=0.7429d0, LAM=0.15d0
  DOUBLE PRECISION, PARAMETER :: KPY=3d5, KPX=8.5d5, CPY=8d3, CPX=1d5, HS=0.9d0, OMS=30d0
  COMPLEX(KIND(1d0)) :: Y, PSI, YD, PSID, FXR, FYR, MZR, FXL, FYL, MZL, FN, FS, MS, PHI, D
  INCLUDE 'scale.inc'
  Y = SC*U(1); PSI = SC*U(2); YD = SC*OMS*U(3); PSID = SC*OMS*U(4)
  CALL SIDEC( 1d0, Y, PSI, YD, PSID, V, MU, FXR, FYR, MZR)
  CALL SIDEC(-1d0, Y, PSI, YD, PSID, V, MU, FXL, FYL, MZL)
  CALL GEOMC(Y, D)
  PHI = D/L0
  FN = -0.5d0*W*(TAN(LAM + PHI) - TAN(LAM - PHI))
  FS = -2d0*KPY*Y - 2d0*CPY*YD
  MS = -2d0*KPX*HS*HS*PSI - 2d0*CPX*HS*HS*PSID
  F(1) = OMS*U(3)
  F(2) = OMS*U(4)
  F(3) = (FYR + FYL + FN + FS)/(XM*OMS*SC)
  F(4) = (L0*(FXL - FXR) + MZR + MZL + MS)/(XIZ*OMS*SC)
END SUBROUTINE FUNCC

SUBROUTINE STPNT(NDIM,U,PAR,T)
  IMPLICIT NONE
  INTEGER, INTENT(IN) :: NDIM
  DOUBLE PRECISION, INTENT(INOUT) :: U(NDIM), PAR(*)
  DOUBLE PRECISION, INTENT(IN) :: T
  U = 0d0
  PAR(1) = 60d0
  PAR(2) = 0d0
  PAR(3) = 0.3d0
END SUBROUTINE STPNT

SUBROUTINE PVLS(NDIM,U,PAR)
  IMPLICIT NONE
  INTEGER, INTENT(IN) :: NDIM
  DOUBLE PRECISION, INTENT(IN) :: U(NDIM)
  DOUBLE PRECISION, INTENT(INOUT) :: PAR(*)
  DOUBLE PRECISION, EXTERNAL :: GETP
  PAR(2) = GETP('MAX',1,U)
END SUBROUTINE PVLS

SUBROUTINE BCND
END SUBROUTINE BCND
SUBROUTINE ICND
END SUBROUTINE ICND
SUBROUTINE FOPT
END SUBROUTINE FOPT
