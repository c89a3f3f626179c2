! Compares bogie.f90's right-hand side with critspeed's at the states that
! `cargo run --release --example vehicle_rhs -- studies/dtu-cooperrider-bogie.toml N` prints
! (one line per state: V, x(12), f(12), SI), read from standard input. For each state it
! prints the largest difference of the accelerations relative to the largest acceleration
! magnitude of the same kind (lateral, yaw) over the six bodies' rows, then the worst. Lines
! that also carry critspeed's exact Jacobian (`--jacobian`, 144 more values, column-major)
! compare it with bogie.f90's complex-step Jacobian (what AUTO gets with JAC = 1), and also
! with central differences of bogie.f90's f (steps 1e-7 m, rad, m/s, rad/s) for scale: the
! largest difference over the lower block relative to the largest entry of its row.
! Built by scripts/auto07p-bogie with bogie.f90 alone (no AUTO objects; GETP is a stub).
PROGRAM BOGIE_RHS_CHECK
  USE BOGIE_MODEL
  IMPLICIT NONE
  DOUBLE PRECISION :: REC(25), X(12), F(12), FR(12), V, WORST, REL, SCALE, U(12), FU(12)
  DOUBLE PRECISION :: DUM1(1,1), DUM2(1,1), PAR(20), WORSTU, JR(12,12), JF(12,12), XP(12), &
       XM(12), FP(12), FM(12), WORSTJ, RELJ, REC2(169), JC(12,12), DV(12), RELC, WORSTC, &
       DFDU(12,12), DFDP(12,2), RELU
  INTEGER :: IOS, N, I, J, ICP(1)
  LOGICAL :: HASJ
  CHARACTER(LEN=20000) :: LINE
  WORST = 0d0; WORSTU = 0d0; WORSTJ = -1d0; WORSTC = -1d0; N = 0
  DO
     READ (*, '(A)', IOSTAT=IOS) LINE
     IF (IOS /= 0) EXIT
     READ (LINE, *, IOSTAT=IOS) REC2
     HASJ = IOS == 0
     IF (HASJ) THEN
        REC = REC2(1:25); JR = RESHAPE(REC2(26:169), (/ 12, 12 /))
     ELSE
        READ (LINE, *, IOSTAT=IOS) REC
        IF (IOS /= 0) EXIT
     END IF
     N = N + 1
     V = REC(1); X = REC(2:13); FR = REC(14:25)
     CALL BOGIE_RHS(X, V, F)
     REL = 0d0
     DO I = 7, 12
        ! relative to the row's own size, floored at 1e-3 of the largest of its kind
        SCALE = MAX(ABS(FR(I)), 1d-3*MAXVAL(ABS(FR(7+MOD(I-7,2):12:2))), TINY(1d0))
        REL = MAX(REL, ABS(F(I) - FR(I))/SCALE)
     END DO
     ! the same through AUTO's FUNC in scaled units
     U(1:6) = 1d3*X(1:6); U(7:12) = 1d3*X(7:12)/OMS
     PAR = 0d0; PAR(1) = V
     CALL FUNC(12, U, ICP, PAR, 0, FU, DUM1, DUM2)
     DO I = 7, 12
        SCALE = MAX(ABS(FR(I)), 1d-3*MAXVAL(ABS(FR(7+MOD(I-7,2):12:2))), TINY(1d0))
        WORSTU = MAX(WORSTU, ABS(FU(I)*OMS*1d-3 - FR(I))/SCALE)
     END DO
     IF (HASJ) THEN
        RELJ = 0d0
        DO J = 1, 12
           XP = X; XM = X
           XP(J) = X(J) + 1d-7; XM(J) = X(J) - 1d-7
           CALL BOGIE_RHS(XP, V, FP)
           CALL BOGIE_RHS(XM, V, FM)
           JF(:,J) = (FP - FM)/2d-7
        END DO
        CALL BOGIE_JAC(X, V, JC, DV)
        ! FUNC's scaled DFDU back in SI
        U(1:6) = 1d3*X(1:6); U(7:12) = 1d3*X(7:12)/OMS
        PAR = 0d0; PAR(1) = V
        CALL FUNC(12, U, ICP, PAR, 2, FU, DFDU, DFDP)
        RELC = 0d0; RELU = 0d0
        DO I = 7, 12
           RELJ = MAX(RELJ, MAXVAL(ABS(JF(I,:) - JR(I,:)))/MAXVAL(ABS(JR(I,:))))
           RELC = MAX(RELC, MAXVAL(ABS(JC(I,:) - JR(I,:)))/MAXVAL(ABS(JR(I,:))))
           RELU = MAX(RELU, MAXVAL(ABS(DFDU(I,1:6)*OMS - JR(I,1:6)))/MAXVAL(ABS(JR(I,:))), &
                MAXVAL(ABS(DFDU(I,7:12) - JR(I,7:12)))/MAXVAL(ABS(JR(I,:))))
        END DO
        WORSTJ = MAX(WORSTJ, RELJ)
        WORSTC = MAX(WORSTC, RELC, RELU)
        WRITE (*, '(A,I4,A,F9.4,A,ES10.2,A,ES10.2,A,ES10.2,A)') 'state', N, '  V', V, &
             '  f', REL, '  J', RELC, '  (central diff.', RELJ, ')'
     ELSE
        WRITE (*, '(A,I4,A,F9.4,A,ES10.2)') 'state', N, '  V', V, '  max rel. diff.', REL
     END IF
     WORST = MAX(WORST, REL)
  END DO
  WRITE (*, '(A,I4,A,ES10.2,A,ES10.2)') 'states:', N, '  worst relative difference:', WORST, &
       '  through FUNC (scaled):', WORSTU
  IF (WORSTJ >= 0d0) WRITE (*, '(A,ES10.2,A,ES10.2,A)') 'worst Jacobian difference:', &
       WORSTC, '  (central differences:', WORSTJ, ')'
END PROGRAM BOGIE_RHS_CHECK

DOUBLE PRECISION FUNCTION GETP(CODE, IC, U)
  CHARACTER(LEN=*), INTENT(IN) :: CODE
  INTEGER, INTENT(IN) :: IC
  DOUBLE PRECISION, INTENT(IN) :: U(*)
  GETP = 0d0
END FUNCTION GETP
