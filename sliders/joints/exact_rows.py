"""The joint rows of :mod:`sliders.joints.exact_laws`, vectorised (generated).

Written by ``python -m sliders.joints.exact_generate`` from the rows' one statement (sympy
traces each row and differentiates it); ``tests/test_exact_joints.py`` checks that
regenerating changes nothing.  Each function evaluates one row of any number of joints at
once: its values, its ``B`` row and its share of ``H`` per unit multiplier.
"""

# ruff: noqa

#: The inputs (name, size) in their order (rotations and frames row-major).
INPUTS = (('x_a', 3), ('R_a', 9), ('x_b', 3), ('R_b', 9), ('p_a', 3), ('p_b', 3), ('F_a', 9), ('F_b', 9))


def row_ux(p, B, H):
    """The row ``ux`` of joints whose inputs are ``p`` (48, n)
    (:data:`INPUTS`): returns its values (n,); writes its ``B`` row into ``B`` (12, n)
    and its share of ``H`` per unit multiplier into ``H`` (12, 12, n), zero on entry."""
    t0 = p[10]*p[33] + p[11]*p[36] + p[30]*p[9]
    t1 = p[21]*p[27]
    t2 = p[22]*p[28]
    t3 = p[23]*p[29]
    t4 = p[10]*p[25] + p[11]*p[26] + p[24]*p[9]
    t5 = p[14] - p[2] + t1 + t2 + t3 - t4
    t6 = p[30]*p[3] + p[33]*p[4] + p[36]*p[5]
    t7 = p[15]*p[27]
    t8 = p[16]*p[28]
    t9 = p[17]*p[29]
    t10 = p[24]*p[3] + p[25]*p[4] + p[26]*p[5]
    t11 = -p[0] + p[12] - t10 + t7 + t8 + t9
    t12 = p[30]*p[6] + p[33]*p[7] + p[36]*p[8]
    t13 = p[24]*p[6]
    t14 = p[25]*p[7]
    t15 = p[26]*p[8]
    t16 = p[18]*p[27] + p[19]*p[28] + p[20]*p[29]
    t17 = p[13] - p[1] - t13 - t14 - t15 + t16
    t18 = -t6
    t19 = -t12
    t20 = -t0
    t21 = t13 + t14 + t15
    t22 = -t21
    t23 = t0*t22 + t12*t5
    t24 = -t4
    t25 = t0*t11 + t24*t6
    t26 = -t10
    t27 = t12*t26 + t17*t6
    t28 = t0*t16
    t29 = t1 + t2 + t3
    t30 = -t29
    t31 = t7 + t8 + t9
    t32 = -t31
    t33 = t29*t6
    t34 = t12*t31
    t35 = -t16
    t36 = t0*t4 + t20*t5
    t37 = t12*t21 + t17*t19
    t38 = t10*t12 + t18*t22
    t39 = t20*t26 + t4*t6
    t40 = t12*t16 + t20*t30
    t41 = t12*t32
    t42 = t20*t31
    t43 = t10*t6 + t11*t18
    t44 = t0*t21 + t19*t24
    t45 = t16*t18
    t46 = t0*t29 + t18*t32
    t47 = t0*t35
    t48 = t30*t6
    t49 = t19*t29
    t50 = t19*t35 + t31*t6
    t51 = t0*t30
    t52 = t12*t35
    t53 = t32*t6
    B[0] = t18
    B[1] = t19
    B[2] = t20
    B[3] = t12*t4 + t17*t20 + t23
    B[4] = t0*t10 + t18*t5 + t25
    B[5] = t11*t19 + t21*t6 + t27
    B[6] = t6
    B[7] = t12
    B[8] = t0
    B[9] = t12*t30 + t28
    B[10] = t0*t32 + t33
    B[11] = t34 + t35*t6
    H[0, 4] = t20
    H[0, 5] = t12
    H[1, 3] = t0
    H[1, 5] = t18
    H[2, 3] = t19
    H[2, 4] = t6
    H[3, 1] = t0
    H[3, 2] = t19
    H[3, 3] = 2*t12*t22 + 2*t20*t4 + t36 + t37
    H[3, 4] = t27 + t38
    H[3, 5] = t0*t26 + t39 + t5*t6
    H[3, 7] = t20
    H[3, 8] = t12
    H[3, 9] = t40
    H[3, 10] = t41
    H[3, 11] = t42
    H[4, 0] = t20
    H[4, 2] = t6
    H[4, 3] = t11*t12 + t22*t6 + t38
    H[4, 4] = 2*t0*t24 + 2*t10*t18 + t36 + t43
    H[4, 5] = t23 + t44
    H[4, 6] = t0
    H[4, 8] = t18
    H[4, 9] = t45
    H[4, 10] = t46
    H[4, 11] = t47
    H[5, 0] = t12
    H[5, 1] = t18
    H[5, 3] = t25 + t39
    H[5, 4] = t0*t17 + t12*t24 + t44
    H[5, 5] = 2*t19*t21 + 2*t26*t6 + t37 + t43
    H[5, 6] = t19
    H[5, 7] = t6
    H[5, 9] = t48
    H[5, 10] = t49
    H[5, 11] = t50
    H[6, 4] = t0
    H[6, 5] = t19
    H[7, 3] = t20
    H[7, 5] = t6
    H[8, 3] = t12
    H[8, 4] = t18
    H[9, 3] = t40
    H[9, 4] = t45
    H[9, 5] = t48
    H[9, 9] = t51 + t52
    H[9, 10] = t34
    H[9, 11] = t0*t31
    H[10, 3] = t41
    H[10, 4] = t46
    H[10, 5] = t49
    H[10, 9] = t16*t6
    H[10, 10] = t51 + t53
    H[10, 11] = t28
    H[11, 3] = t42
    H[11, 4] = t47
    H[11, 5] = t50
    H[11, 9] = t33
    H[11, 10] = t12*t29
    H[11, 11] = t52 + t53
    return t0*t5 + t11*t6 + t12*t17


def row_rx(p, B, H):
    """The row ``rx`` of joints whose inputs are ``p`` (48, n)
    (:data:`INPUTS`): returns its values (n,); writes its ``B`` row into ``B`` (12, n)
    and its share of ``H`` per unit multiplier into ``H`` (12, 12, n), zero on entry."""
    t0 = p[10]*p[34] + p[11]*p[37] + p[31]*p[9]
    t1 = p[21]*p[41] + p[22]*p[44] + p[23]*p[47]
    t2 = t0*t1
    t3 = p[15]*p[41] + p[16]*p[44] + p[17]*p[47]
    t4 = p[31]*p[3] + p[34]*p[4] + p[37]*p[5]
    t5 = t3*t4
    t6 = p[18]*p[41] + p[19]*p[44] + p[20]*p[47]
    t7 = p[31]*p[6] + p[34]*p[7] + p[37]*p[8]
    t8 = t6*t7
    t9 = -t0
    t10 = t1*t7
    t11 = t0*t3
    t12 = -t4
    t13 = -t7
    t14 = t4*t6
    t15 = t0*t6
    t16 = -t1
    t17 = -t3
    t18 = t1*t4
    t19 = t3*t7
    t20 = -t6
    t21 = t13*t6
    t22 = t1*t9
    t23 = t16*t9 + t8
    t24 = t17*t7
    t25 = t3*t9
    t26 = t12*t3
    t27 = t12*t6
    t28 = t12*t17 + t2
    t29 = t0*t20
    t30 = t16*t4
    t31 = t1*t13
    t32 = t13*t20 + t5
    t33 = t0*t16
    t34 = t20*t7
    t35 = t17*t4
    B[3] = t10 + t6*t9
    B[4] = t1*t12 + t11
    B[5] = t13*t3 + t14
    B[9] = t15 + t16*t7
    B[10] = t0*t17 + t18
    B[11] = t19 + t20*t4
    H[3, 3] = t21 + t22
    H[3, 4] = t14
    H[3, 5] = t18
    H[3, 9] = t23
    H[3, 10] = t24
    H[3, 11] = t25
    H[4, 3] = t19
    H[4, 4] = t22 + t26
    H[4, 5] = t10
    H[4, 9] = t27
    H[4, 10] = t28
    H[4, 11] = t29
    H[5, 3] = t11
    H[5, 4] = t15
    H[5, 5] = t21 + t26
    H[5, 9] = t30
    H[5, 10] = t31
    H[5, 11] = t32
    H[9, 3] = t23
    H[9, 4] = t27
    H[9, 5] = t30
    H[9, 9] = t33 + t34
    H[9, 10] = t19
    H[9, 11] = t11
    H[10, 3] = t24
    H[10, 4] = t28
    H[10, 5] = t31
    H[10, 9] = t14
    H[10, 10] = t33 + t35
    H[10, 11] = t15
    H[11, 3] = t25
    H[11, 4] = t29
    H[11, 5] = t32
    H[11, 9] = t18
    H[11, 10] = t10
    H[11, 11] = t34 + t35
    return t2 + t5 + t8


#: The function of each row.
ROW_FUNCTIONS = {'ux': row_ux, 'rx': row_rx}
