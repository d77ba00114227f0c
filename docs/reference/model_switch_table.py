import json, subprocess, resource, os
import sys
B=sys.argv[1] if len(sys.argv) > 1 else 'target/release/stickslip'
kc=0.011
fr=[0.999,0.99,0.95,0.9,0.8,0.7,0.6,0.5]
ks=','.join('%.10g'%(f*kc) for f in fr)
def run(args):
    r0=resource.getrusage(resource.RUSAGE_CHILDREN)
    p=subprocess.run([B,'cycles','--json','--out','/tmp/stickslip-model-switch-table']+args,capture_output=True,text=True)
    r1=resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu=(r1.ru_utime-r0.ru_utime)+(r1.ru_stime-r0.ru_stime)
    d=json.loads(p.stdout)
    return d,cpu,p.returncode
res={}
for name,args in [('qs',['--model','quasi-static']),('in',['--model','inertial']),('auto',[])]:
    d,cpu,rc=run(args+['--at-kappa',ks])
    pts={}
    for c in d['cycles']:
        if c['user_point']:
            pts[round(c['kappa']/kc,6)]=c
    res[name]=(pts,cpu,rc,len(d['cycles']),d['cycles'][-1]['kappa']/kc, d.get('model_switch'))
    print(name,'cpu %.2f s'%cpu,'rc',rc,'cycles',len(d['cycles']),'end %.4f'%(d['cycles'][-1]['kappa']/kc), 'max ntst', max(c['ntst'] for c in d['cycles']))
print()
print('| kappa/kappa_c | chi (QS orbit) | T QS | T inertial | rel. diff | Delta_s QS | Delta_s inertial | rel. diff | v_max QS | v_max inertial |')
print('|---|---|---|---|---|---|---|---|---|---|')
for f in fr:
    q=res['qs'][0].get(round(f,6)); i=res['in'][0].get(round(f,6))
    if not q or not i: print(f,'missing'); continue
    print('| %.3f | %.2e | %.6e | %.6e | %.1e | %.6e | %.6e | %.1e | %.3e | %.3e |'%(f,q['inertial_imbalance'],q['period'],i['period'],abs(q['period']/i['period']-1),q['delta_s'],i['delta_s'],abs(q['delta_s']/i['delta_s']-1),q['v_max'],i['v_max']))
print(res['auto'][5])
for f in fr:
    a=res['auto'][0].get(round(f,6)); i=res['in'][0].get(round(f,6))
    if a and i: print(f, a['model'], abs(a['period']/i['period']-1), abs(a['delta_s']/i['delta_s']-1))
