package dev.motionfusion.cli

/**
 * A parsed command line: options (`--name value`, `--name=value`, `-o value`, `--flag`) and
 * positional arguments. [valued] and [flags] list what the command accepts; anything else is a
 * [UsageException].
 */
internal class Options(args: List<String>, valued: Set<String>, flags: Set<String>) {
    private val values = LinkedHashMap<String, String>()
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
                val name = if (eq > 0) a.substring(0, eq) else a
                when {
                    name in valued -> {
                        val v = if (eq > 0) a.substring(eq + 1) else args.getOrNull(++i) ?: throw UsageException("$name needs a value")
                        values[name] = v
                    }
                    name in flags && eq < 0 -> set += name
                    else -> throw UsageException("unknown option '$a'")
                }
            }
            i++
        }
    }

    fun has(flag: String): Boolean = flag in set
    fun value(name: String): String? = values[name]

    fun double(name: String): Double? = values[name]?.let {
        it.toDoubleOrNull()?.takeIf { d -> d.isFinite() } ?: throw UsageException("$name expects a number, got '$it'")
    }

    fun long(name: String): Long? = values[name]?.let { it.toLongOrNull() ?: throw UsageException("$name expects an integer, got '$it'") }
}
