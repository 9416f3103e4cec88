import re,sys,glob,collections,statistics
out=sys.argv[1]
vals=collections.defaultdict(dict)
for f in sorted(glob.glob(out+'/*.txt')):
    w,r=f.split('/')[-1][:-4].split('-')
    lines=open(f).read().splitlines()
    try: i=[k for k,l in enumerate(lines) if 'core-ns/ps' in l][-1]
    except IndexError: continue
    for l in lines[i+1:]:
        p=l.split()
        if len(p)<5: break
        vals[(p[0],int(p[1]))][(w,int(r))]=float(p[3])
for k in sorted(vals):
    v=vals[k]
    rounds=sorted(set(r for (_,r) in v))
    ratios=[v[('a',r)]/v[('b',r)] for r in rounds if ('a',r) in v and ('b',r) in v]
    a=[v[('a',r)] for r in rounds if ('a',r) in v]; b=[v[('b',r)] for r in rounds if ('b',r) in v]
    print('%-12s %8d  main %s  new %s  main/new %s median %.3f'%(k[0],k[1],' '.join('%.1f'%x for x in a),' '.join('%.1f'%x for x in b),' '.join('%.3f'%x for x in ratios), statistics.median(ratios) if ratios else float('nan')))
