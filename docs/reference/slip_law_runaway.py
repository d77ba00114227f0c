"""Issue 27: Gu, Rice, Ruina & Weeks (1984) found steady sliding under the
plain slip law linearly stable above kappa_c but unstable to finite
perturbations. This maps that threshold with `stickslip simulate` (the
release binary; build it first): the plain quasi-static slip law (mu2 = 0,
PMMA's A = 0.012, B = 0.023, nu = 1, kappa_c = 0.011) started from steady
sliding with its state perturbed, theta0 = (1 + perturb)/nu, bisected in
perturb between a run that decays to steady sliding and one whose slip
velocity runs away (the integrator stops where v blows up: exit 4, the run
kept up to there, partial). The ageing law at the threshold perturbation
is run for comparison.

Then, independently of stickslip, whether the runaway is a blow-up of the
quasi-static model or a failure of the integrator: the same equations
integrated in the slip s = int v dt (in D0; dt = ds / v, so a velocity
that diverges at a finite time t* takes an infinite slip to do so and
t(s) converges to t*), with x = ln v, y = ln theta:

    dx/ds = [kappa (nu e^-x - 1) + (B + 2 mu2 y) (x + y)] / A
    dy/ds = -(x + y),       dt/ds = e^-x

by classical Runge-Kutta (ds = 1e-3) until v = e^700 (blow-up: t has
converged) or s = 200. Analytically, for mu2 = 0 with phi = ln(v theta):
d phi/dt = [kappa nu + v ((B - A) phi - kappa)] / A, so once (B - A) phi >
kappa phi keeps growing, and d ln v/dt = [kappa nu + v (B phi - kappa)]/A
>= kappa v / (B - A): dv/dt >= kappa v^2 / (B - A), a blow-up before
t + (B - A)/(kappa v). With the ln^2 term (the PMMA scene's mu2 =
2.4e-4) the effective B + 2 mu2 ln theta falls below A where theta <
exp(-(B - A)/(2 mu2)), and the velocity turns back. Both are run at
1.05 kappa_c on both sides of the threshold, and compared with stickslip's
runs (its peak log10 v and where it stops).

Run: python3 slip_law_runaway.py > slip_law_runaway_out.txt
"""
import subprocess, json
import os, tempfile
S=os.path.join(os.path.dirname(os.path.abspath(__file__)),'..','..','target','release','stickslip')
OUT=tempfile.mkdtemp()
import glob, math
def simulate(k, pert, law='slip', mu2=0.0):
    out=tempfile.mkdtemp(dir=OUT)
    r=subprocess.run([S,'simulate','--json','--force','--set','state_law='+law,'--set','mu2=%r'%mu2,'--set','kappa=%r'%k,'--model','quasi-static','--perturb=%r'%pert,'--protocol','1:400','--out',out],capture_output=True,text=True)
    return r, out
def runaway(k, pert, law='slip'):
    r,_=simulate(k, pert, law)
    # The velocity blowing up ends the run early: kept, partial (exit 4).
    if r.returncode==4 and 'blows up' in r.stderr: return True
    d=json.loads(r.stdout)
    if r.returncode==0 and d['regime'] and d['regime']['kind']=='steady': return False
    raise SystemExit('unexpected run at kappa=%r perturb=%r (exit %d): %s'%(k,pert,r.returncode,r.stderr))
def peak(k, pert, mu2):
    """stickslip's run: its peak log10 v, the t (D0/V0) where the run ends, complete or not."""
    r,out=simulate(k, pert, 'slip', mu2)
    f=glob.glob(out+'/*-simulation.csv')[0]
    rows=[l.strip().split(',') for l in open(f) if not l.startswith('#')]
    i,it=rows[0].index('log10_v'),rows[0].index('t')
    return max(float(r[i]) for r in rows[1:]), float(rows[-1][it]), r.returncode==0
def independent(p, kappa, mu2, A=0.012, B=0.023, nu=1.0, ds=1e-3, s_max=200.0):
    y=math.log1p(p); x=-(B*y+mu2*y*y)/A
    def f(z):
        x,y,t=z
        ex=math.exp(-x)
        return ((kappa*(nu*ex-1)+(B+2*mu2*y)*(x+y))/A, -(x+y), ex)
    z=(x,y,0.0); top=(x,0.0); s=0.0
    while s<s_max:
        k1=f(z); k2=f(tuple(a+0.5*ds*b for a,b in zip(z,k1)))
        k3=f(tuple(a+0.5*ds*b for a,b in zip(z,k2))); k4=f(tuple(a+ds*b for a,b in zip(z,k3)))
        z=tuple(a+ds/6*(b+2*c+2*d+e) for a,b,c,d,e in zip(z,k1,k2,k3,k4)); s+=ds
        if z[0]>top[0]: top=(z[0],z[2])
        if z[0]>700: return 'blow-up', top[0]/math.log(10), z[2]
    return 'bounded', top[0]/math.log(10), z[2]
kc=0.011
for f in [1.02,1.05,1.2,1.5,2.0]:
    lo,hi=-0.999,-0.01   # runaway at lo (strong weakening), not at hi
    if not runaway(kc*f, lo): print(f, 'no runaway even at', lo); continue
    if runaway(kc*f, hi): print(f,'runaway at', hi); continue
    for _ in range(14):
        mid=(lo+hi)/2
        if runaway(kc*f, mid): lo=mid
        else: hi=mid
    print('kappa/kappa_c=%g: runaway for perturb <= %.4f (theta0 nu = %.4f, initial v jump x %.3g)'%(f, lo, 1+lo, (1+lo)**(-0.023/0.012)), 'ageing law at that perturbation:', 'runaway' if runaway(kc*f, lo, 'ageing') else 'steady')
print()
print('at kappa = 1.05 kappa_c: stickslip simulate (quasi-static, slip law) against the independent integration in slip')
for mu2 in [0.0, 2.4e-4]:
    for p in [-0.6,-0.65,-0.659,-0.66,-0.67,-0.75,-0.9,-0.99]:
        top,end,complete=peak(1.05*kc,p,mu2)
        kind,itop,t=independent(p,1.05*kc,mu2)
        print('mu2=%g perturb=%g: stickslip peak log10 v = %.4g, %s at t = %.7g D0/V0; independent: %s, peak log10 v = %.4g %s t = %.7g D0/V0'%(
            mu2,p,top,'ran to its end' if complete else 'stopped (v blows up)',end,kind,itop,'(v = e^700) at' if kind=='blow-up' else 'by',t))
