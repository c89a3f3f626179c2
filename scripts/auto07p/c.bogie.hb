# DTU Cooperrider bogie (bogie.f90): the centred equilibrium continued in V from 60 m/s until
# the Hopf point (HB), with exact derivatives (JAC=1: with AUTO's difference quotients V_H is
# 1.5e-6 too high, see bogie.f90)
NDIM=12, IPS=1, IRS=0, ILP=0
ICP=[1,2]
NTST=50, NCOL=4, IAD=3, ISP=1, ISW=1, IPLT=0, NBC=0, NINT=0
NMX=200, NPR=1000, MXBF=0, IID=0, ITMX=8, ITNW=7, NWTN=3, JAC=1
EPSL=1e-10, EPSU=1e-10, EPSS=1e-6
DS=0.5, DSMIN=1e-6, DSMAX=2.0, IADS=1
THL={}, THU={}
STOP=['HB1']
UZSTOP={1: 300.0}
