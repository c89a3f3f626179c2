"""Writes the rows of studies/tables/cubic-fold.csv: r_R(y) = r0 + 0.15 y + 2000 y^3 on
knife-edge rails (roll = (r_R - r_L)/(2 l0), delta_R = 0.15 + roll), y from -20 mm to 20 mm
every 0.5 mm. The header comment of the CSV is kept by hand."""
LAM, KAP, L0, R0 = 0.15, 2000.0, 0.7429, 0.46
print("y_m,r_m,delta_rad,roll_rad")
for i in range(-40, 41):
    y = i * 0.0005
    d = LAM * y + KAP * y**3
    print(f"{y:.4f},{R0 + d:.17g},{LAM + d / L0:.17g},{d / L0:.17g}")
