# bash completion for visctl(1): commands, global and per-command options, the values of
# --engine, --engines, --kinds and --role, gen's kinds, stack's above|below, and files for SCENE,
# FILE, CSV and SVG arguments. Self-contained: it needs none of bash-completion's helpers.
# Installed as `visctl` into bash-completion's completionsdir; or source it from ~/.bashrc.

_visctl_commands="compute gen bench plot-service create destroy map unmap move resize raise
	lower stack border shape opaque load states tree region repaint look lookup snapshot watch script
	sync
	stress help"
_visctl_engines="auto gmv gmv-heap region brute"
_visctl_kinds="random uniform grid cascade tiles nested shaped translucent"

# The options of a command (global ones for ""), then those that take a value.
_visctl_options() {
	case $1 in
	"") echo "-s --socket --role -h --help --version" ;;
	compute) echo "--engine --visible --json --time --svg --help" ;;
	bench) echo "--kinds --engines --sizes --max-n --reps --seed --limit --svg --csv --quick --family --min-n --help" ;;
	plot-service) echo "--note --help" ;;
	create) echo "--parent --map --retain --border --input-only --x11 --external --help" ;;
	shape) echo "--box --help" ;;
	load) echo "--retain --any-screen --json --help" ;;
	states) echo "--json --x11 --names --help" ;;
	tree | region | repaint | look) echo "--json --help" ;;
	lookup) echo "--x11 --help" ;;
	snapshot) echo "--svg --help" ;;
	watch) echo "--json --count --x11 --help" ;;
	stress) echo "-c -n --count --duration -R --pipeline --mix --batch-size --exposure --scene
		--seed --record --pid --json --csv -q --quiet --help" ;;
	*) echo "--help" ;;
	esac
}

# Whether option $2 of command $1 ("" for the global ones) takes a value.
_visctl_takes_value() {
	case $1:$2 in
	:-s | :--socket | :--role) return 0 ;;
	compute:--engine | compute:--svg | plot-service:--note | create:--parent) return 0 ;;
	create:--border | create:--x11 | create:--external | lookup:--x11) return 0 ;;
	snapshot:--svg | watch:--count) return 0 ;;
	bench:--kinds | bench:--engines | bench:--sizes | bench:--max-n | bench:--reps) return 0 ;;
	bench:--seed | bench:--limit | bench:--svg | bench:--csv | bench:--family | bench:--min-n) return 0 ;;
	stress:-c | stress:-n | stress:--count | stress:--duration | stress:-R) return 0 ;;
	stress:--pipeline | stress:--mix | stress:--batch-size | stress:--seed) return 0 ;;
	stress:--record | stress:--pid | stress:--scene) return 0 ;;
	esac
	return 1
}

# Files and directories matching $1, marked so that readline adds a slash to directories.
_visctl_files() {
	compopt -o filenames 2>/dev/null
	mapfile -t COMPREPLY < <(compgen -f -- "$1")
}

# Completes the value $2 of option $1; $3 goes before each word (for --opt=VALUE in one word).
_visctl_value() {
	local opt=$1 cur=$2 prefix=$3
	case $opt in
	--engine) mapfile -t COMPREPLY < <(compgen -P "$prefix" -W "$_visctl_engines" -- "$cur") ;;
	--role) mapfile -t COMPREPLY < <(compgen -P "$prefix" -W "client observer manager" -- "$cur") ;;
	--scene)
		mapfile -t COMPREPLY < <(compgen -P "$prefix" -W "random uniform grid cascade tiles nested" \
			-- "$cur")
		;;
	--engines | --kinds)
		# A comma-separated list: complete its last item.
		local words=$_visctl_kinds
		[ "$opt" = --engines ] && words=$_visctl_engines
		local head=
		case $cur in *,*) head=${cur%,*}, ;; esac
		mapfile -t COMPREPLY < <(compgen -P "$prefix$head" -W "$words" -- "${cur##*,}")
		compopt -o nospace 2>/dev/null
		;;
	-s | --socket | --svg | --csv | --record)
		if [ -n "$prefix" ]; then
			mapfile -t COMPREPLY < <(compgen -P "$prefix" -f -- "$cur")
		else
			_visctl_files "$cur"
		fi
		;;
	*) COMPREPLY=() ;;
	esac
}

_visctl() {
	local cword=$COMP_CWORD cur=${COMP_WORDS[COMP_CWORD]}
	local cmd='' i=1 w n=0 opt=''
	COMPREPLY=()

	# With '=' in COMP_WORDBREAKS (the default), --opt=VALUE is three words: --opt, =, VALUE.
	local prev=''
	((cword > 0)) && prev=${COMP_WORDS[cword - 1]}
	if [ "$cur" = "=" ]; then
		opt=$prev
		cur=
	elif [ "$prev" = "=" ] && ((cword > 1)); then
		opt=${COMP_WORDS[cword - 2]}
	fi

	# Find the command and count its positional arguments before the word being completed.
	while ((i < cword)); do
		w=${COMP_WORDS[i]}
		if [ "${COMP_WORDS[i + 1]}" = "=" ]; then
			i=$((i + 3)) # --opt = VALUE
			continue
		fi
		if [ -z "$cmd" ]; then
			case $w in
			-*) _visctl_takes_value "" "$w" && i=$((i + 1)) ;;
			*) cmd=$w ;;
			esac
		else
			case $w in
			-) n=$((n + 1)) ;;
			--*=*) ;;
			-*) _visctl_takes_value "$cmd" "$w" && i=$((i + 1)) ;;
			*) n=$((n + 1)) ;;
			esac
		fi
		i=$((i + 1))
	done

	# A value: after --opt=, or after an option that takes one.
	if [ -n "$opt" ]; then
		_visctl_value "$opt" "$cur" ""
		return 0
	fi
	case $cur in
	--*=*)
		_visctl_value "${cur%%=*}" "${cur#*=}" "${cur%%=*}="
		return 0
		;;
	esac
	if ((cword > 1)) && _visctl_takes_value "$cmd" "$prev"; then
		_visctl_value "$prev" "$cur" ""
		return 0
	fi

	if [[ $cur == -* ]]; then
		mapfile -t COMPREPLY < <(compgen -W "$(_visctl_options "$cmd")" -- "$cur")
		return 0
	fi
	if [ -z "$cmd" ]; then
		mapfile -t COMPREPLY < <(compgen -W "$_visctl_commands" -- "$cur")
		return 0
	fi
	case $cmd:$n in
	gen:0) mapfile -t COMPREPLY < <(compgen -W "$_visctl_kinds" -- "$cur") ;;
	stack:1) mapfile -t COMPREPLY < <(compgen -W "above below" -- "$cur") ;;
	compute:0 | load:0 | script:0 | plot-service:[01]) _visctl_files "$cur" ;;
	esac
	return 0
}

complete -F _visctl visctl
