package dev.motionfusion.cli

/**
 * A parsed command line: options (`--name value`, `--name=value`, `-o value`, `--flag`) and
 * positional arguments. [valued] and [flags] list what the command accepts; anything else is a
 * [UsageException]. A valued option given twice, under either of its spellings ([ALIASES]: `-o` and
 * `--output`), is one too, unless it is [REPEATABLE] (its values then all count, in order: [values]);
 * a later value never silently replaces an earlier one.
 */
internal class Options(args: List<String>, valued: Set<String>, flags: Set<String>) {
    private val values = LinkedHashMap<String, String>()
    private val repeated = LinkedHashMap<String, MutableList<String>>()
    private val set = HashSet<String>()
    val positional = ArrayList<String>()

    init {
        var i = 0
        var onlyPositional = false
        while (i < args.size) {
            val a = args[i]
            if (onlyPositional || !a.startsWith("-") || a == "-") {
                positional += a
            } else if (a == "--") {
                onlyPositional = true
            } else {
                val eq = a.indexOf('=')
                val given = if (eq > 0) a.substring(0, eq) else a
                val name = ALIASES[given] ?: given
                when {
                    given in valued -> {
                        val v = if (eq > 0) a.substring(eq + 1) else args.getOrNull(++i) ?: throw UsageException("$given needs a value")
                        val earlier = values.put(name, v)
                        if (earlier != null && name !in REPEATABLE) {
                            val shown = ALIASES.entries.firstOrNull { it.value == name }?.let { "$name/${it.key}" } ?: name
                            throw UsageException("$shown given twice ('$earlier', then '$v'); give it once")
                        }
                        repeated.getOrPut(name) { ArrayList() } += v
                    }
                    given in flags && eq < 0 -> set += given
                    else -> throw UsageException("unknown option '$a'")
                }
            }
            i++
        }
    }

    fun has(flag: String): Boolean = flag in set
    /** The value of [name] (either spelling); for a repeatable option, the last one ([values] has them all). */
    fun value(name: String): String? = values[ALIASES[name] ?: name]

    /** Every value given to [name], in order. */
    fun values(name: String): List<String> = repeated[ALIASES[name] ?: name].orEmpty()

    fun double(name: String): Double? = value(name)?.let {
        it.toDoubleOrNull()?.takeIf { d -> d.isFinite() } ?: throw UsageException("$name expects a number, got '$it'")
    }

    fun long(name: String): Long? = value(name)?.let { it.toLongOrNull() ?: throw UsageException("$name expects an integer, got '$it'") }

    companion object {
        /** The options that may be given more than once: each `--set NAME=VALUE` adds to the others. */
        val REPEATABLE = setOf("--set")

        /** Two spellings of one option: given once each, they are the option given twice. */
        val ALIASES = mapOf("--output" to "-o")
    }
}
