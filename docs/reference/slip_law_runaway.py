"""Issue 27: Gu, Rice, Ruina & Weeks (1984) found steady sliding under the
plain slip law linearly stable above kappa_c but unstable to finite
perturbations. This maps that threshold with `stickslip simulate` (the
release binary; build it first): the plain quasi-static slip law (mu2 = 0,
PMMA's A = 0.012, B = 0.023, nu = 1, kappa_c = 0.011) started from steady
sliding with its state perturbed, theta0 = (1 + perturb)/nu, bisected in
perturb between a run that decays to steady sliding and one whose slip
velocity runs away (the quasi-static block has no inertia to bound it; the
integrator stops where v blows up). The ageing law at the threshold
perturbation is run for comparison.

Run: python3 slip_law_runaway.py > slip_law_runaway_out.txt
"""
import subprocess, json
import os, tempfile
S=os.path.join(os.path.dirname(os.path.abspath(__file__)),'..','..','target','release','stickslip')
OUT=tempfile.mkdtemp()
def runaway(k, pert, law='slip'):
    r=subprocess.run([S,'simulate','--json','--force','--set','state_law='+law,'--set','mu2=0','--set','kappa=%r'%k,'--model','quasi-static','--perturb=%r'%pert,'--protocol','1:400','--out',OUT],capture_output=True,text=True)
    if r.returncode==3 and 'blows up' in r.stderr: return True
    d=json.loads(r.stdout); return False if d['regime'] and d['regime']['kind']=='steady' else None
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
