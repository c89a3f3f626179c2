!----------------------------------------------------------------------
! AUTO-07p right-hand side of critspeed's bogie (docs/model.md §11, layout "bogie", no frame
! roll: 12 states) for studies/dtu-cooperrider-bogie.toml, run by scripts/auto07p-bogie.
!
! Bodies and state order as critspeed's Vehicle: q = (y1, psi1, y2, psi2, yf, psif) for the
! leading wheelset (x = +a), the trailing one (x = -a) and the frame; x = (q, qdot).
! Elements (per side s = +1 right, -1 left), the force on the first end
! F = -diag(k) Delta - diag(c) Delta_dot with Delta = u_A - u_B, u_x = -p_y psi,
! u_y = y + p_x psi (no roll state, so no u_z and no vertical element acts):
!   primary   wheelset point (0, s d, 0) to frame point (+-a, s d, .), k = (Kpx, Kpy, .)
!   secondary frame point (0, s ds, .) to the track, k = (Ksx, Ksy, .), c = (Csx, Csy, .)
!   yaw damper frame point (0, s dyd, .) to the track, c = (Cyd, 0, 0)
! generalised forces Q_y = F_y, Q_psi = p_x F_y - p_y F_x on A, minus those on B.
! Contact on each wheelset (docs/model.md §3-5): the right wheel's r, delta, f11..f33 at y, the
! left wheel's at -y, from critspeed's contact table: the file's rows splined not-a-knot
! (cubic, C2), sampled on the study's grid (401 nodes over +-8 mm) with exact slopes, the
! Hertz semi-axes scaled to N = (W/2)/cos(delta) by a, b ~ N^(1/3), f11 = G ab C11,
! f22 = G ab C22, f23 = G (ab)^1.5 C23, f33 = G (ab)^2 C33 with C33 from Kalker's table
! (monotone cubic Hermite in ln(a/b), linear in nu), second derivatives at the nodes (the
! spline's for r and delta, central differences of the node slopes for f11..f33), and a
! quintic Hermite interpolant between the nodes, continued linearly beyond them.
! Creepages, Shen-Hedrick-Elkins saturation (mu = 0.15, spin on) and gravitational stiffness
! as scripts/auto07p/wheelset.f90. No flange.
! Derivatives (JAC = 1 in c.bogie.*): FUNC also returns DFDU and DFDP(:,1) (d/dV): the
! elements' constant part, and each wheelset's contact forces by complex-step differentiation
! of a complex copy of TABLE, WHEEL and CONTACT (TABLEZ, WHEELZ, CONTACTZ: keep them identical
! to the real ones). With AUTO's own difference quotients (JAC = 0, step 1e-7 of a scaled unit,
! 1e-10 m at the centre) the rounding of r(y)/r0 in the longitudinal creepage makes the
! Jacobian's rows wrong by about 1.4e-6: V_H moves by 1.5e-6 and the multipliers by 1e-5.
! Everything here is written from docs/model.md and critspeed's source (src/model/,
! src/contact/), not from another code; the data come from bogie-table.inc, which
! scripts/auto07p/bogie-table.py writes from the two CSV files.
! State in scaled units: U(1..6) = q in mm and mrad, U(7..12) = qdot/OMS in mm and mrad,
! OMS = 60 rad/s (near the hunting frequency, 10 Hz); PAR(1) = V (m/s); PAR(2) = max y of the
! leading wheelset (mm, PVLS); PAR(11) = period (s).
!----------------------------------------------------------------------
MODULE BOGIE_MODEL
  IMPLICIT NONE
  INCLUDE 'bogie-table.inc'
  ! wheelset (the contact's)
  DOUBLE PRECISION, PARAMETER :: W=133316d0, R0=0.4248829d0, L0=0.75d0
  DOUBLE PRECISION, PARAMETER :: XMW=1022d0, XIW=678d0
  ! primary per side
  DOUBLE PRECISION, PARAMETER :: KPY=1.823d6, KPX=3.646d6, CPY=0d0, CPX=0d0, DP=0.62d0
  ! frame
  DOUBLE PRECISION, PARAMETER :: XMF=2918.9d0, XIF=6780d0, AH=1.074d0
  ! secondary per side, yaw dampers
  DOUBLE PRECISION, PARAMETER :: KSY=1.823d5, KSX=9.0335d5, CSY=2.92d4, CSX=0d0, DS=1.5d0
  DOUBLE PRECISION, PARAMETER :: CYD=1.66669d5, DYD=1.5d0
  ! contact
  DOUBLE PRECISION, PARAMETER :: MU=0.15d0, EY=210d9, NU=0.27d0
  DOUBLE PRECISION, PARAMETER :: GS=EY/(2d0*(1d0+NU))
  ! the sampled table: NG nodes over +-YW, NC columns r, delta, f11, f22, f23, f33
  INTEGER, PARAMETER :: NG=401, NC=6
  DOUBLE PRECISION, PARAMETER :: YW=8d-3
  DOUBLE PRECISION, PARAMETER :: OMS=60d0
  DOUBLE PRECISION, PARAMETER :: XMASS(6) = (/ XMW, XIW, XMW, XIW, XMF, XIF /)
  DOUBLE PRECISION, SAVE :: GY0, GH, COEF(0:5,NC,NG-1), LASTV(NC), LASTS(NC)
  LOGICAL, SAVE :: READY=.FALSE.
CONTAINS

  SUBROUTINE SPLINE_M(N, X, V, M)
    ! second derivatives M of the not-a-knot cubic spline through (X, V): the interior
    ! equations h(i-1) M(i-1) + 2 (h(i-1)+h(i)) M(i) + h(i) M(i+1) = 6 (D(i) - D(i-1)) and
    ! the third derivative continuous at X(2) and X(N-1); dense Gauss with partial pivoting
    INTEGER, INTENT(IN) :: N
    DOUBLE PRECISION, INTENT(IN) :: X(N), V(N)
    DOUBLE PRECISION, INTENT(OUT) :: M(N)
    DOUBLE PRECISION :: A(N,N), B(N), H(N-1), D(N-1), P, T(N)
    INTEGER :: I, J, K, IP
    DO I = 1, N-1
       H(I) = X(I+1) - X(I)
       D(I) = (V(I+1) - V(I))/H(I)
    END DO
    A = 0d0; B = 0d0
    A(1,1) = -H(2); A(1,2) = H(1) + H(2); A(1,3) = -H(1)
    DO I = 2, N-1
       A(I,I-1) = H(I-1); A(I,I) = 2d0*(H(I-1) + H(I)); A(I,I+1) = H(I)
       B(I) = 6d0*(D(I) - D(I-1))
    END DO
    A(N,N-2) = -H(N-1); A(N,N-1) = H(N-2) + H(N-1); A(N,N) = -H(N-2)
    DO K = 1, N-1
       IP = K
       DO I = K+1, N
          IF (ABS(A(I,K)) > ABS(A(IP,K))) IP = I
       END DO
       IF (IP /= K) THEN
          T = A(K,:); A(K,:) = A(IP,:); A(IP,:) = T
          P = B(K); B(K) = B(IP); B(IP) = P
       END IF
       DO I = K+1, N
          P = A(I,K)/A(K,K)
          IF (P /= 0d0) THEN
             A(I,K:N) = A(I,K:N) - P*A(K,K:N)
             B(I) = B(I) - P*B(K)
          END IF
       END DO
    END DO
    DO I = N, 1, -1
       P = B(I)
       DO J = I+1, N
          P = P - A(I,J)*M(J)
       END DO
       M(I) = P/A(I,I)
    END DO
  END SUBROUTINE SPLINE_M

  SUBROUTINE SPLINE_EVAL(N, X, V, M, Y, S0, S1, S2)
    ! value, slope and second derivative of the spline at Y (interval with X(K) <= Y,
    ! clamped to the end intervals)
    INTEGER, INTENT(IN) :: N
    DOUBLE PRECISION, INTENT(IN) :: X(N), V(N), M(N), Y
    DOUBLE PRECISION, INTENT(OUT) :: S0, S1, S2
    DOUBLE PRECISION :: H, A, B
    INTEGER :: K
    K = 1
    DO WHILE (K < N-1 .AND. X(K+1) <= Y)
       K = K + 1
    END DO
    H = X(K+1) - X(K); A = X(K+1) - Y; B = Y - X(K)
    S0 = (M(K)*A**3 + M(K+1)*B**3)/(6d0*H) + (V(K)/H - M(K)*H/6d0)*A &
         + (V(K+1)/H - M(K+1)*H/6d0)*B
    S1 = (V(K+1) - V(K))/H + (M(K+1)*B*B - M(K)*A*A)/(2d0*H) - (M(K+1) - M(K))*H/6d0
    S2 = (M(K)*A + M(K+1)*B)/H
  END SUBROUTINE SPLINE_EVAL

  SUBROUTINE PCHIP(N, X, Y, D)
    ! Fritsch-Carlson monotone slopes: weighted harmonic mean of the secants inside (zero
    ! where they change sign), the three-point end formula limited to keep the end monotone
    INTEGER, INTENT(IN) :: N
    DOUBLE PRECISION, INTENT(IN) :: X(N), Y(N)
    DOUBLE PRECISION, INTENT(OUT) :: D(N)
    DOUBLE PRECISION :: H(N-1), S(N-1), W1, W2
    INTEGER :: K
    DO K = 1, N-1
       H(K) = X(K+1) - X(K); S(K) = (Y(K+1) - Y(K))/H(K)
    END DO
    D = 0d0
    DO K = 2, N-1
       IF (S(K-1)*S(K) > 0d0) THEN
          W1 = 2d0*H(K) + H(K-1); W2 = H(K) + 2d0*H(K-1)
          D(K) = (W1 + W2)/(W1/S(K-1) + W2/S(K))
       END IF
    END DO
    D(1) = PEND(H(1), H(2), S(1), S(2))
    D(N) = PEND(H(N-1), H(N-2), S(N-1), S(N-2))
  END SUBROUTINE PCHIP

  DOUBLE PRECISION FUNCTION PEND(H0, H1, D0, D1)
    DOUBLE PRECISION, INTENT(IN) :: H0, H1, D0, D1
    PEND = ((2d0*H0 + H1)*D0 - H0*D1)/(H0 + H1)
    IF (PEND*D0 <= 0d0) THEN
       PEND = 0d0
    ELSE IF (D0*D1 < 0d0 .AND. ABS(PEND) > 3d0*ABS(D0)) THEN
       PEND = 3d0*D0
    END IF
  END FUNCTION PEND

  SUBROUTINE KALKER33(Q, C, DC)
    ! Kalker's C33 at a/b = Q and NU, and dC33/d(a/b)
    DOUBLE PRECISION, INTENT(IN) :: Q
    DOUBLE PRECISION, INTENT(OUT) :: C, DC
    DOUBLE PRECISION, SAVE :: KT(NKAL), YA(NKAL), YB(NKAL), DA(NKAL), DB(NKAL)
    LOGICAL, SAVE :: SORTED=.FALSE.
    DOUBLE PRECISION :: T, WN, H, S, V0, V1, E0, E1, TMP
    INTEGER :: I, J, K
    IF (.NOT. SORTED) THEN
       KT = KSIGN*LOG(KG); YA = K33A; YB = K33B
       DO I = 2, NKAL  ! insertion sort by t
          DO J = I, 2, -1
             IF (KT(J-1) <= KT(J)) EXIT
             TMP = KT(J); KT(J) = KT(J-1); KT(J-1) = TMP
             TMP = YA(J); YA(J) = YA(J-1); YA(J-1) = TMP
             TMP = YB(J); YB(J) = YB(J-1); YB(J-1) = TMP
          END DO
       END DO
       CALL PCHIP(NKAL, KT, YA, DA)
       CALL PCHIP(NKAL, KT, YB, DB)
       SORTED = .TRUE.
    END IF
    IF (.NOT. (Q >= 0.1d0 .AND. Q <= 10d0)) STOP 'a/b outside Kalker''s table'
    T = MIN(MAX(LOG(Q), KT(1)), KT(NKAL))
    K = 1
    DO WHILE (K < NKAL-1 .AND. KT(K+1) <= T)
       K = K + 1
    END DO
    WN = (NU - 0.25d0)/(0.5d0 - 0.25d0)
    H = KT(K+1) - KT(K); S = (T - KT(K))/H
    CALL HERM(YA(K), YA(K+1), H*DA(K), H*DA(K+1), S, V0, E0)
    CALL HERM(YB(K), YB(K+1), H*DB(K), H*DB(K+1), S, V1, E1)
    C = (1d0 - WN)*V0 + WN*V1
    DC = ((1d0 - WN)*E0 + WN*E1)/H/Q
  END SUBROUTINE KALKER33

  SUBROUTINE HERM(Y0, Y1, M0, M1, S, V, DV)
    ! cubic Hermite on [0, 1] in S: value and d/dS
    DOUBLE PRECISION, INTENT(IN) :: Y0, Y1, M0, M1, S
    DOUBLE PRECISION, INTENT(OUT) :: V, DV
    V = Y0*(1d0 - S)**2*(1d0 + 2d0*S) + Y1*S*S*(3d0 - 2d0*S) + M0*S*(1d0 - S)**2 &
        - M1*S*S*(1d0 - S)
    DV = 6d0*S*(1d0 - S)*(Y1 - Y0) + M0*(1d0 - S)*(1d0 - 3d0*S) + M1*S*(3d0*S - 2d0)
  END SUBROUTINE HERM

  SUBROUTINE TABINIT
    ! the study's contact table: node values, slopes and second derivatives, then the
    ! quintic Hermite coefficients of every interval (in powers of y - y_k)
    DOUBLE PRECISION :: MR(NROW), MD(NROW), MA(NROW), MB(NROW), M11(NROW), M22(NROW), &
         M23(NROW), MN(NROW)
    DOUBLE PRECISION :: VAL(NC,NG), SLO(NC,NG), CUR(NC,NG)
    DOUBLE PRECISION :: Y, R, R1, D, D1, A, A1, B, B1, XN, XN1, E, C11, C11D, C22, C22D, &
         C23, C23D, X2
    DOUBLE PRECISION :: FN, FN1, RHO, RHO1, SC, SC1, AA, AA1, BB, BB1, Q, Q1, C33, DC33, &
         AB, AB1, P0, P1, PM0, PM1, PC0, PC1, DEL, A3, A4, A5
    INTEGER :: K, C, HALF
    CALL SPLINE_M(NROW, TY, TR, MR)
    CALL SPLINE_M(NROW, TY, TD, MD)
    CALL SPLINE_M(NROW, TY, TA, MA)
    CALL SPLINE_M(NROW, TY, TB, MB)
    CALL SPLINE_M(NROW, TY, T11, M11)
    CALL SPLINE_M(NROW, TY, T22, M22)
    CALL SPLINE_M(NROW, TY, T23, M23)
    CALL SPLINE_M(NROW, TY, TN, MN)
    HALF = (NG - 1)/2
    GH = YW/HALF
    GY0 = -HALF*GH
    DO K = 1, NG
       ! critspeed solves node k at y = +-j h, j = |k - HALF - 1|
       Y = (K - 1 - HALF)*GH
       CALL SPLINE_EVAL(NROW, TY, TR, MR, Y, R, R1, X2)
       CALL SPLINE_EVAL(NROW, TY, TD, MD, Y, D, D1, X2)
       CALL SPLINE_EVAL(NROW, TY, TA, MA, Y, A, A1, X2)
       CALL SPLINE_EVAL(NROW, TY, TB, MB, Y, B, B1, X2)
       CALL SPLINE_EVAL(NROW, TY, TN, MN, Y, XN, XN1, X2)
       CALL SPLINE_EVAL(NROW, TY, T11, M11, Y, C11, C11D, X2)
       CALL SPLINE_EVAL(NROW, TY, T22, M22, Y, C22, C22D, X2)
       CALL SPLINE_EVAL(NROW, TY, T23, M23, Y, C23, C23D, X2)
       ! model normal force N = (W/2)/cos(delta); Hertz a, b ~ N^(1/3)
       FN = 0.5d0*W/COS(D)
       FN1 = 0.5d0*W*SIN(D)/COS(D)**2*D1
       RHO = FN/XN
       RHO1 = (FN1*XN - FN*XN1)/XN**2
       SC = RHO**(1d0/3d0)
       SC1 = RHO1*SC/(3d0*RHO)
       AA = A*SC; AA1 = A1*SC + A*SC1
       BB = B*SC; BB1 = B1*SC + B*SC1
       Q = AA/BB; Q1 = (AA1*BB - AA*BB1)/BB**2
       CALL KALKER33(Q, C33, DC33)
       AB = AA*BB; AB1 = AA1*BB + AA*BB1
       VAL(1,K) = R; SLO(1,K) = R1
       VAL(2,K) = D; SLO(2,K) = D1
       VAL(3,K) = GS*AB*C11; SLO(3,K) = GS*(AB1*C11 + AB*C11D)
       VAL(4,K) = GS*AB*C22; SLO(4,K) = GS*(AB1*C22 + AB*C22D)
       VAL(5,K) = GS*AB*SQRT(AB)*C23
       SLO(5,K) = GS*(1.5d0*SQRT(AB)*AB1*C23 + AB*SQRT(AB)*C23D)
       VAL(6,K) = GS*AB*AB*C33
       SLO(6,K) = GS*(2d0*AB*AB1*C33 + AB*AB*DC33*Q1)
       ! the spline's second derivatives of r and delta at the grid's y0 + k h
       Y = GY0 + (K - 1)*GH
       CALL SPLINE_EVAL(NROW, TY, TR, MR, Y, E, X2, CUR(1,K))
       CALL SPLINE_EVAL(NROW, TY, TD, MD, Y, E, X2, CUR(2,K))
    END DO
    ! the other columns: central differences of the node slopes, one-sided at the ends
    DO C = 3, NC
       CUR(C,1) = (-3d0*SLO(C,1) + 4d0*SLO(C,2) - SLO(C,3))/(2d0*GH)
       CUR(C,NG) = (3d0*SLO(C,NG) - 4d0*SLO(C,NG-1) + SLO(C,NG-2))/(2d0*GH)
       DO K = 2, NG-1
          CUR(C,K) = (SLO(C,K+1) - SLO(C,K-1))/(2d0*GH)
       END DO
    END DO
    ! quintic Hermite per interval: value, slope, second derivative at both ends
    DO K = 1, NG-1
       DO C = 1, NC
          P0 = VAL(C,K); P1 = VAL(C,K+1)
          PM0 = SLO(C,K)*GH; PM1 = SLO(C,K+1)*GH
          PC0 = CUR(C,K)*GH*GH; PC1 = CUR(C,K+1)*GH*GH
          DEL = P1 - P0
          A3 = 10d0*DEL - 6d0*PM0 - 4d0*PM1 - 1.5d0*PC0 + 0.5d0*PC1
          A4 = -15d0*DEL + 8d0*PM0 + 7d0*PM1 + 1.5d0*PC0 - PC1
          A5 = 6d0*DEL - 3d0*(PM0 + PM1) - 0.5d0*(PC0 - PC1)
          COEF(0,C,K) = P0
          COEF(1,C,K) = SLO(C,K)
          COEF(2,C,K) = 0.5d0*CUR(C,K)
          COEF(3,C,K) = A3/GH**3
          COEF(4,C,K) = A4/GH**4
          COEF(5,C,K) = A5/GH**5
       END DO
    END DO
    LASTV = VAL(:,NG); LASTS = SLO(:,NG)
    READY = .TRUE.
  END SUBROUTINE TABINIT

  SUBROUTINE TABLE(Y, OUT)
    ! the right wheel's r, delta, f11, f22, f23, f33 at Y (m)
    DOUBLE PRECISION, INTENT(IN) :: Y
    DOUBLE PRECISION, INTENT(OUT) :: OUT(NC)
    DOUBLE PRECISION :: S, DD
    INTEGER :: K, C
    IF (.NOT. READY) THEN
       !$OMP CRITICAL (BOGIE_TABLE)
       IF (.NOT. READY) CALL TABINIT
       !$OMP END CRITICAL (BOGIE_TABLE)
    END IF
    S = (Y - GY0)/GH
    IF (S < 0d0) THEN
       DD = Y - GY0
       OUT = COEF(0,:,1) + COEF(1,:,1)*DD
    ELSE IF (S >= NG - 1) THEN
       DD = Y - (GY0 + (NG - 1)*GH)
       OUT = LASTV + LASTS*DD
    ELSE
       K = MIN(INT(S), NG - 2)
       DD = Y - (GY0 + K*GH)
       DO C = 1, NC
          OUT(C) = COEF(0,C,K+1) + DD*(COEF(1,C,K+1) + DD*(COEF(2,C,K+1) + DD*(COEF(3,C,K+1) &
               + DD*(COEF(4,C,K+1) + DD*COEF(5,C,K+1)))))
       END DO
    END IF
  END SUBROUTINE TABLE

  SUBROUTINE WHEEL(SG, T, PSI, YD, PSID, V, FX, FY, MZ, TD)
    ! creep forces on one wheel (side SG) from its table state T, after the Shen law;
    ! TD = tan(delta) for the gravitational stiffness
    DOUBLE PRECISION, INTENT(IN) :: SG, T(NC), PSI, YD, PSID, V
    DOUBLE PRECISION, INTENT(OUT) :: FX, FY, MZ, TD
    DOUBLE PRECISION :: XIX, XIY, OM, XN, BETA, EPS
    XIX = 1d0 - T(1)/R0 - SG*L0*PSID/V
    XIY = YD/V - PSI
    OM = PSID/V - SG*SIN(T(2))/R0
    FX = -T(3)*XIX
    FY = -T(4)*XIY - T(5)*OM
    MZ = T(5)*XIY - T(6)*OM
    XN = 0.5d0*W/COS(T(2))
    BETA = SQRT(FX*FX + FY*FY)/(MU*XN)
    IF (BETA < 3d0) THEN
       EPS = 1d0 - BETA/3d0 + BETA*BETA/27d0
    ELSE
       EPS = 1d0/BETA
    END IF
    FX = EPS*FX; FY = EPS*FY; MZ = EPS*MZ
    TD = TAN(T(2))
  END SUBROUTINE WHEEL

  SUBROUTINE CONTACT(Y, PSI, YD, PSID, V, QY, QPSI)
    ! the generalised contact forces on one wheelset (N, N m)
    DOUBLE PRECISION, INTENT(IN) :: Y, PSI, YD, PSID, V
    DOUBLE PRECISION, INTENT(OUT) :: QY, QPSI
    DOUBLE PRECISION :: TR_(NC), TL_(NC), FXR, FYR, MZR, TDR, FXL, FYL, MZL, TDL
    CALL TABLE(Y, TR_)
    CALL TABLE(-Y, TL_)
    CALL WHEEL( 1d0, TR_, PSI, YD, PSID, V, FXR, FYR, MZR, TDR)
    CALL WHEEL(-1d0, TL_, PSI, YD, PSID, V, FXL, FYL, MZL, TDL)
    QY = FYR + FYL - 0.5d0*W*(TDR - TDL)
    QPSI = L0*(FXL - FXR) + MZR + MZL
  END SUBROUTINE CONTACT

  SUBROUTINE ELEMENTS(Q, QD, G)
    ! the generalised forces of the spring-damper elements (linear in q, qdot)
    DOUBLE PRECISION, INTENT(IN) :: Q(6), QD(6)
    DOUBLE PRECISION, INTENT(OUT) :: G(6)
    DOUBLE PRECISION :: S, XW, DX, DY, DDX, DDY, FX, FY
    INTEGER :: K, J, IY, IP
    G = 0d0
    DO K = 1, 2
       IY = 2*K - 1; IP = 2*K
       XW = AH*(3 - 2*K)  ! +a leading, -a trailing
       DO J = 1, 2
          S = 3 - 2*J  ! +1 right, -1 left
          ! primary: wheelset (0, s d, 0) to frame (xw, s d, .)
          DX = -S*DP*Q(IP) + S*DP*Q(6)
          DY = Q(IY) - (Q(5) + XW*Q(6))
          DDX = -S*DP*QD(IP) + S*DP*QD(6)
          DDY = QD(IY) - (QD(5) + XW*QD(6))
          FX = -KPX*DX - CPX*DDX
          FY = -KPY*DY - CPY*DDY
          G(IY) = G(IY) + FY
          G(IP) = G(IP) - S*DP*FX
          G(5) = G(5) - FY
          G(6) = G(6) - (XW*FY - S*DP*FX)
       END DO
    END DO
    DO J = 1, 2
       S = 3 - 2*J
       ! secondary: frame (0, s ds, .) to the track
       FX = -KSX*(-S*DS*Q(6)) - CSX*(-S*DS*QD(6))
       FY = -KSY*Q(5) - CSY*QD(5)
       G(5) = G(5) + FY
       G(6) = G(6) - S*DS*FX
       ! yaw damper: frame (0, s dyd, .) to the track, along x
       FX = -CYD*(-S*DYD*QD(6))
       G(6) = G(6) - S*DYD*FX
    END DO
  END SUBROUTINE ELEMENTS

  SUBROUTINE BOGIE_RHS(X, V, F)
    ! f(x; V) in SI: x = (y1, psi1, y2, psi2, yf, psif, and their rates)
    DOUBLE PRECISION, INTENT(IN) :: X(12), V
    DOUBLE PRECISION, INTENT(OUT) :: F(12)
    DOUBLE PRECISION :: G(6), QY, QPSI
    INTEGER :: K, IY, IP
    CALL ELEMENTS(X(1:6), X(7:12), G)
    DO K = 1, 2
       IY = 2*K - 1; IP = 2*K
       CALL CONTACT(X(IY), X(IP), X(6+IY), X(6+IP), V, QY, QPSI)
       G(IY) = G(IY) + QY
       G(IP) = G(IP) + QPSI
    END DO
    F(1:6) = X(7:12)
    F(7:12) = G/XMASS
  END SUBROUTINE BOGIE_RHS

  ! ---- derivatives for AUTO (JAC = 1): complex-step copies of TABLE, WHEEL and CONTACT,
  ! d g/d z = Im g(z + i H)/H, exact to rounding; the real path above must be kept identical

  SUBROUTINE TABLEZ(Y, OUT)
    COMPLEX(KIND=8), INTENT(IN) :: Y
    COMPLEX(KIND=8), INTENT(OUT) :: OUT(NC)
    COMPLEX(KIND=8) :: DD
    DOUBLE PRECISION :: S
    INTEGER :: K, C
    IF (.NOT. READY) THEN
       !$OMP CRITICAL (BOGIE_TABLE)
       IF (.NOT. READY) CALL TABINIT
       !$OMP END CRITICAL (BOGIE_TABLE)
    END IF
    S = (DBLE(Y) - GY0)/GH
    IF (S < 0d0) THEN
       DD = Y - GY0
       OUT = COEF(0,:,1) + COEF(1,:,1)*DD
    ELSE IF (S >= NG - 1) THEN
       DD = Y - (GY0 + (NG - 1)*GH)
       OUT = LASTV + LASTS*DD
    ELSE
       K = MIN(INT(S), NG - 2)
       DD = Y - (GY0 + K*GH)
       DO C = 1, NC
          OUT(C) = COEF(0,C,K+1) + DD*(COEF(1,C,K+1) + DD*(COEF(2,C,K+1) + DD*(COEF(3,C,K+1) &
               + DD*(COEF(4,C,K+1) + DD*COEF(5,C,K+1)))))
       END DO
    END IF
  END SUBROUTINE TABLEZ

  SUBROUTINE WHEELZ(SG, T, PSI, YD, PSID, V, FX, FY, MZ, TD)
    DOUBLE PRECISION, INTENT(IN) :: SG
    COMPLEX(KIND=8), INTENT(IN) :: T(NC), PSI, YD, PSID, V
    COMPLEX(KIND=8), INTENT(OUT) :: FX, FY, MZ, TD
    COMPLEX(KIND=8) :: XIX, XIY, OM, XN, BETA, EPS
    XIX = 1d0 - T(1)/R0 - SG*L0*PSID/V
    XIY = YD/V - PSI
    OM = PSID/V - SG*SIN(T(2))/R0
    FX = -T(3)*XIX
    FY = -T(4)*XIY - T(5)*OM
    MZ = T(5)*XIY - T(6)*OM
    XN = 0.5d0*W/COS(T(2))
    BETA = SQRT(FX*FX + FY*FY)/(MU*XN)
    IF (DBLE(BETA) < 3d0) THEN
       EPS = 1d0 - BETA/3d0 + BETA*BETA/27d0
    ELSE
       EPS = 1d0/BETA
    END IF
    FX = EPS*FX; FY = EPS*FY; MZ = EPS*MZ
    TD = TAN(T(2))
  END SUBROUTINE WHEELZ

  SUBROUTINE CONTACTZ(Y, PSI, YD, PSID, V, QY, QPSI)
    COMPLEX(KIND=8), INTENT(IN) :: Y, PSI, YD, PSID, V
    COMPLEX(KIND=8), INTENT(OUT) :: QY, QPSI
    COMPLEX(KIND=8) :: TR_(NC), TL_(NC), FXR, FYR, MZR, TDR, FXL, FYL, MZL, TDL
    CALL TABLEZ(Y, TR_)
    CALL TABLEZ(-Y, TL_)
    CALL WHEELZ( 1d0, TR_, PSI, YD, PSID, V, FXR, FYR, MZR, TDR)
    CALL WHEELZ(-1d0, TL_, PSI, YD, PSID, V, FXL, FYL, MZL, TDL)
    QY = FYR + FYL - 0.5d0*W*(TDR - TDL)
    QPSI = L0*(FXL - FXR) + MZR + MZL
  END SUBROUTINE CONTACTZ

  SUBROUTINE BOGIE_JAC(X, V, DFDX, DFDV)
    ! the Jacobian d f/d x (12 x 12) and d f/d V in SI: the elements' part from their linear
    ! forces at unit vectors, each wheelset's contact part by complex steps in its 4 states
    DOUBLE PRECISION, INTENT(IN) :: X(12), V
    DOUBLE PRECISION, INTENT(OUT) :: DFDX(12,12), DFDV(12)
    DOUBLE PRECISION, PARAMETER :: H=1d-30
    DOUBLE PRECISION :: E(12), G(6)
    COMPLEX(KIND=8) :: Z(4), ZV, QY, QPSI
    INTEGER :: J, K, IY, IP, COLS(4)
    DFDX = 0d0; DFDV = 0d0
    DO J = 1, 6
       DFDX(J,6+J) = 1d0
    END DO
    DO J = 1, 12
       E = 0d0; E(J) = 1d0
       CALL ELEMENTS(E(1:6), E(7:12), G)
       DFDX(7:12,J) = G
    END DO
    DO K = 1, 2
       IY = 2*K - 1; IP = 2*K
       COLS = (/ IY, IP, 6+IY, 6+IP /)
       DO J = 1, 4
          Z = CMPLX(X(COLS), 0d0, KIND=8)
          Z(J) = CMPLX(X(COLS(J)), H, KIND=8)
          CALL CONTACTZ(Z(1), Z(2), Z(3), Z(4), CMPLX(V, 0d0, KIND=8), QY, QPSI)
          DFDX(6+IY,COLS(J)) = DFDX(6+IY,COLS(J)) + AIMAG(QY)/H
          DFDX(6+IP,COLS(J)) = DFDX(6+IP,COLS(J)) + AIMAG(QPSI)/H
       END DO
       Z = CMPLX(X(COLS), 0d0, KIND=8)
       ZV = CMPLX(V, H, KIND=8)
       CALL CONTACTZ(Z(1), Z(2), Z(3), Z(4), ZV, QY, QPSI)
       DFDV(6+IY) = AIMAG(QY)/H
       DFDV(6+IP) = AIMAG(QPSI)/H
    END DO
    DO J = 1, 12
       DFDX(7:12,J) = DFDX(7:12,J)/XMASS
    END DO
    DFDV(7:12) = DFDV(7:12)/XMASS
  END SUBROUTINE BOGIE_JAC
END MODULE BOGIE_MODEL

SUBROUTINE FUNC(NDIM,U,ICP,PAR,IJAC,F,DFDU,DFDP)
  USE BOGIE_MODEL
  IMPLICIT NONE
  INTEGER, INTENT(IN) :: NDIM, ICP(*), IJAC
  DOUBLE PRECISION, INTENT(IN) :: U(NDIM), PAR(*)
  DOUBLE PRECISION, INTENT(OUT) :: F(NDIM)
  DOUBLE PRECISION, INTENT(INOUT) :: DFDU(NDIM,NDIM), DFDP(NDIM,*)
  DOUBLE PRECISION :: X(12), FX(12), DFDX(12,12), DFDV(12)
  INTEGER :: J
  X(1:6) = 1d-3*U(1:6)
  X(7:12) = 1d-3*OMS*U(7:12)
  CALL BOGIE_RHS(X, PAR(1), FX)
  F(1:6) = OMS*U(7:12)
  F(7:12) = 1d3*FX(7:12)/OMS
  IF (IJAC == 0) RETURN
  ! JAC = 1: the exact derivatives, in the scaled units
  CALL BOGIE_JAC(X, PAR(1), DFDX, DFDV)
  DFDU = 0d0
  DO J = 1, 6
     DFDU(J,6+J) = OMS
     DFDU(7:12,J) = DFDX(7:12,J)/OMS
     DFDU(7:12,6+J) = DFDX(7:12,6+J)
  END DO
  IF (IJAC == 1) RETURN
  DFDP(:,1:2) = 0d0
  DFDP(7:12,1) = 1d3*DFDV(7:12)/OMS
END SUBROUTINE FUNC

SUBROUTINE STPNT(NDIM,U,PAR,T)
  IMPLICIT NONE
  INTEGER, INTENT(IN) :: NDIM
  DOUBLE PRECISION, INTENT(INOUT) :: U(NDIM), PAR(*)
  DOUBLE PRECISION, INTENT(IN) :: T
  U = 0d0
  PAR(1) = 60d0
  PAR(2) = 0d0
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
