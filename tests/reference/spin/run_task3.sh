#!/bin/sh
# Task 3: min-peak-torque flip with spin (and L = 0 for comparison)
PY=/tmp/xcheck-venv/bin/python
nice -n 10 $PY mintime_spin.py minpeak --L 0,0,0.01 --N 100,200 --starts 45:0.75:1,45:1:1 --tag _Lz0.01_pos > t3_Lz_pos.txt 2>&1
nice -n 10 $PY mintime_spin.py minpeak --L 0,0,0.01 --N 100,200 --starts 45:0.75:-1,45:1:-1 --tag _Lz0.01_neg > t3_Lz_neg.txt 2>&1
nice -n 10 $PY mintime_spin.py minpeak --L 0,0,0 --N 100,200 --tag _L0 > t3_L0.txt 2>&1
