from mpmath import mp, mpf, sqrt, atan, sin, cos, quad, acos, odefun, nstr
mp.dps = 90
g = mpf('9.81'); b = mpf('0.2'); h = mpf('0.6')
R = sqrt(b*b+h*h); al = atan(b/h); p2 = 3*g/(4*R)
e = 1 - mpf(3)/2*sin(al)**2
def fall(thm):
    # theta = thm - s^2; p2 (cos(al-thm) - cos(al-theta)) = 2 p2 sin((phi+phim)/2) sin(s^2/2)
    phim = al - thm
    def f(s):
        if s == 0: return 2/sqrt(2*p2*sin(phim))  # limit: 2s/sqrt(4 p2 sin(phim) s^2/2)
        phi = phim + s*s
        return 2*s/sqrt(4*p2*sin((phi+phim)/2)*sin(s*s/2))
    return quad(f, [0, sqrt(thm)])
th0 = al/2
t = fall(th0); w = sqrt(2*p2*(cos(al-th0)-cos(al)))
times=[t]; rates=[w]
for k in range(320):
    wp = e*w
    thm = al - acos(cos(al) + wp**2/(2*p2))
    t += 2*fall(thm); w = wp
    times.append(t); rates.append(w)
print('alpha', nstr(al,17), 'e', e, 'p2', nstr(p2,20))
for i in range(15): print(i+1, nstr(times[i],17), nstr(rates[i],17))
print('t_inf ~', nstr(times[-1],17), 'last intervals ratio', nstr((times[-1]-times[-2])/(times[-2]-times[-3]),10))
# state at t = 1.0: after impact 2 at times[1], theta=0, rate e*rates[1]
F = lambda tt, y: [y[1], -p2*sin(al - y[0])]
y = odefun(F, times[1], [mpf(0), e*rates[1]])
print('theta(1.0)', nstr(y(mpf(1))[0],17), 'rate', nstr(y(mpf(1))[1],17))
print('lambda/m at rest (torque) g b =', g*b)
