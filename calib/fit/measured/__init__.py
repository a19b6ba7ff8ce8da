"""The vz law fitted to measurements of one specimen, without an FE model (``nfdcal fit-data``).

Drop tests e(v_in) and quasi-static force-approach curves of a sphere on a rigid flat give
sigma_Y [Pa], Ca_hat, Kc_hat [-] (hence Ca [m/N], Kc [1/N]; Vu-Quoc & Zhang 1999, Proc. R. Soc.
Lond. A 455) with standard errors, an identifiability report and a model choice by AICc. One
idea per module, each importing only those above it:

    data             what was measured: the CSV files, checked (Measurements)
    specimen         the tested specimen and what the law predicts for the data; the residuals
    domain           where the law can be evaluated; the residuals continued smoothly beyond
    scatter          whether a fit's residual is the data's scatter (chi-square, lack of fit)
    regression       one least-squares fit: parameters, covariance, AIC, the law's window
    identifiability  which parameters the data determine; which drop tests would add most
    models           the constrained and the free model, and the choice between them (AICc)
    diagnosis        the likely cause of data the law does not fit (units, columns, material)
    imprint          the measured imprint radius: its prediction, refusals and model-form level
    table_law        the constrained model on the vz master table's load-dependent law
    table_refusal    when that fit is no fit (residual ceiling, interval, window) and why
    bands            the fitted e(v_in) with its confidence band (delta method)
    rate_fit         sigma_Y and one rate constant on the rate-aware vz-table law (drop tests at several speeds)
"""
