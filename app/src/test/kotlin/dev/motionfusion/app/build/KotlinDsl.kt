package dev.motionfusion.app.build

/**
 * A reader for the subset of Kotlin the project's Gradle scripts are written in: calls with
 * arguments and trailing blocks, chains (`tasks.withType<Test>().configureEach { … }`),
 * assignments, `val`/`fun` declarations, string literals (with templates kept as text), numbers,
 * infix and binary operators, lambdas with parameters. It gives the scripts' structure so that the
 * mirror test can ask "which `systemProperty` calls sit in a test task's block" instead of
 * matching lines. What it does not understand is a [KotlinDsl.SyntaxError] naming file, line and
 * column, never a silent skip.
 */
internal object KotlinDsl {
    class SyntaxError(message: String) : RuntimeException(message)

    enum class T { IDENT, STRING, NUMBER, OP, EOF }

    data class Token(val type: T, val text: String, val line: Int, val column: Int, val newlineBefore: Boolean)

    sealed class Node {
        abstract val line: Int
    }

    /** A string literal; [text] keeps `${…}` templates as written, [plain] says there are none. */
    data class Str(val text: String, val plain: Boolean, override val line: Int) : Node()
    data class Num(val text: String, override val line: Int) : Node()
    data class Name(val name: String, override val line: Int) : Node()
    data class Member(val receiver: Node, val name: String, override val line: Int) : Node()
    data class Arg(val name: String?, val value: Node)
    data class Lambda(val params: List<String>, val body: List<Node>, override val line: Int) : Node()
    data class Call(val callee: Node, val typeArgs: List<String>, val args: List<Arg>, val lambda: Lambda?, override val line: Int) : Node() {
        /** The called name: `configureEach` for `tasks.withType<Test>().configureEach { }`. */
        val name: String get() = when (callee) { is Name -> callee.name; is Member -> callee.name; else -> "" }
    }
    data class Binary(val op: String, val left: Node, val right: Node, override val line: Int) : Node()
    data class Unary(val op: String, val operand: Node, override val line: Int) : Node()
    data class Assign(val target: Node, val op: String, val value: Node, override val line: Int) : Node()
    /**
     * `val x = …`, `val x by …`, `fun R.f(…) { … }`, `import …`, `class C : S { … }`: [value] is the
     * initializer or body (a class's body as a [Lambda]); [annotations] as written without `@`
     * (`get:InputFile`, `get:PathSensitive(PathSensitivity.NONE)` is `get:PathSensitive`), [modifiers]
     * (`abstract`, `override` …), [type] a property's declared type, [supertypes] a class's.
     */
    data class Decl(
        val kind: String, val name: String, val value: Node?, override val line: Int,
        val annotations: List<String> = emptyList(), val modifiers: List<String> = emptyList(),
        val type: String? = null, val supertypes: List<String> = emptyList(),
        /** An annotation's arguments by its name, e.g. `get:PathSensitive` → `PathSensitivity.NONE`. */
        val annotationArgs: Map<String, List<Node>> = emptyMap(),
    ) : Node()

    fun parse(source: String, file: String): List<Node> = Parser(tokenize(source, file), file).script()

    // --- tokens ---

    private val ops = listOf("?.", "?:", "::", "->", "==", "!=", "<=", ">=", "&&", "||", "+=", "-=", "..", "!!") +
        listOf("(", ")", "{", "}", "[", "]", "<", ">", ",", ".", ":", ";", "=", "+", "-", "*", "/", "%", "!", "?", "@")

    fun tokenize(s: String, file: String): List<Token> {
        val out = ArrayList<Token>()
        var i = 0
        var line = 1
        var lineStart = 0
        var nl = false
        fun err(msg: String): Nothing = throw SyntaxError("$file:$line:${i - lineStart + 1}: $msg")
        while (i < s.length) {
            val c = s[i]
            val col = i - lineStart + 1
            when {
                c == '\n' -> { i++; line++; lineStart = i; nl = true }
                c.isWhitespace() -> i++
                s.startsWith("//", i) -> while (i < s.length && s[i] != '\n') i++
                s.startsWith("/*", i) -> {
                    val end = s.indexOf("*/", i + 2).takeIf { it >= 0 } ?: err("unterminated comment")
                    for (k in i until end) if (s[k] == '\n') { line++; lineStart = k + 1; nl = true }
                    i = end + 2
                }
                c == '"' -> {
                    val raw = s.startsWith("\"\"\"", i)
                    val startLine = line
                    val sb = StringBuilder()
                    var plain = true
                    i += if (raw) 3 else 1
                    while (true) {
                        if (i >= s.length) err("unterminated string")
                        val d = s[i]
                        if (raw && s.startsWith("\"\"\"", i)) { i += 3; break }
                        if (!raw && d == '"') { i++; break }
                        if (!raw && d == '\n') err("newline in string")
                        if (d == '\n') { line++; lineStart = i + 1 }
                        if (!raw && d == '\\') {
                            val e = s.getOrNull(i + 1) ?: err("unterminated string")
                            sb.append(when (e) { 'n' -> '\n'; 't' -> '\t'; 'r' -> '\r'; else -> e })
                            i += 2
                            continue
                        }
                        if (d == '$' && (s.getOrNull(i + 1) == '{' || s.getOrNull(i + 1)?.isJavaIdentifierStart() == true)) {
                            plain = false
                            if (s[i + 1] == '{') {
                                var depth = 0
                                val start = i
                                while (true) {
                                    if (i >= s.length) err("unterminated template")
                                    if (s[i] == '{') depth++
                                    if (s[i] == '}') { depth--; if (depth == 0) { i++; break } }
                                    i++
                                }
                                sb.append(s, start, i)
                                continue
                            }
                        }
                        sb.append(d)
                        i++
                    }
                    out += Token(T.STRING, (if (plain) "P" else "T") + sb, startLine, col, nl)
                    nl = false
                }
                c.isDigit() -> {
                    val start = i
                    while (i < s.length && (s[i].isLetterOrDigit() || s[i] == '_' || (s[i] == '.' && s.getOrNull(i + 1)?.isDigit() == true))) i++
                    out += Token(T.NUMBER, s.substring(start, i), line, col, nl); nl = false
                }
                c.isJavaIdentifierStart() || c == '`' -> {
                    val start = i
                    if (c == '`') { i = s.indexOf('`', i + 1).takeIf { it >= 0 }?.plus(1) ?: err("unterminated `name`") }
                    else while (i < s.length && s[i].isJavaIdentifierPart()) i++
                    out += Token(T.IDENT, s.substring(start, i).trim('`'), line, col, nl); nl = false
                }
                else -> {
                    val op = ops.firstOrNull { s.startsWith(it, i) } ?: err("unexpected character '$c'")
                    i += op.length
                    out += Token(T.OP, op, line, col, nl); nl = false
                }
            }
        }
        out += Token(T.EOF, "", line, i - lineStart + 1, true)
        return out
    }

    // --- syntax ---

    private class Parser(val t: List<Token>, val file: String) {
        var p = 0
        val peek get() = t[p]
        fun at(text: String, type: T = T.OP) = peek.type == type && peek.text == text
        fun next() = t[p++]
        fun err(msg: String, tok: Token = peek): Nothing = throw SyntaxError("$file:${tok.line}:${tok.column}: $msg (at '${tok.text.let { if (tok.type == T.STRING) it.drop(1) else it }}')")
        fun expect(text: String): Token = if (at(text)) next() else err("expected '$text'")
        fun ident(): String = if (peek.type == T.IDENT) next().text else err("expected a name")

        fun script(): List<Node> = statements(T.EOF)

        fun statements(endType: T, end: String? = null): List<Node> {
            val out = ArrayList<Node>()
            while (!(peek.type == endType && (end == null || peek.text == end))) {
                if (at(";")) { next(); continue }
                if (peek.type == T.EOF) err("unexpected end of file")
                out += statement()
                if (!(peek.newlineBefore || at(";") || at("}") || peek.type == T.EOF)) err("expected the end of the statement")
            }
            return out
        }

        private val MODIFIERS = setOf("abstract", "override", "private", "internal", "public", "protected", "open", "lateinit", "inline", "data", "final")

        /** `@name`, `@get:Name`, `@Name(args)` before a declaration. */
        fun annotation(): Pair<String, List<Node>> {
            expect("@")
            val sb = StringBuilder(ident())
            if (at(":")) { next(); sb.append(':').append(ident()) }
            while (at(".")) { next(); sb.append('.').append(ident()) }
            val args = ArrayList<Node>()
            if (at("(") && !peek.newlineBefore) {
                next()
                while (!at(")")) { args += expression(); if (at(",")) next() else if (!at(")")) err("expected ',' or ')'") }
                next()
            }
            return sb.toString() to args
        }

        fun statement(): Node {
            val annotations = ArrayList<Pair<String, List<Node>>>()
            val modifiers = ArrayList<String>()
            while (true) {
                if (at("@")) { annotations += annotation(); continue }
                if (peek.type == T.IDENT && peek.text in MODIFIERS && t[p + 1].type == T.IDENT) { modifiers += next().text; continue }
                break
            }
            val decl = declaration()
            if (decl != null) return decl.copy(annotations = annotations.map { it.first }, modifiers = modifiers, annotationArgs = annotations.toMap())
            if (annotations.isNotEmpty() || modifiers.isNotEmpty()) err("expected a declaration after its annotations or modifiers")
            return expressionStatement()
        }

        fun declaration(): Decl? {
            val tok = peek
            if (tok.type == T.IDENT && tok.text == "class") {
                next()
                val name = ident()
                if (at("@")) annotation()
                if (at("constructor", T.IDENT)) next()
                if (at("(")) { next(); while (!at(")")) { if (at("val", T.IDENT) || at("var", T.IDENT)) next(); ident(); expect(":"); type(); if (at("=")) { next(); expression() }; if (at(",")) next() }; next() }
                val supertypes = ArrayList<String>()
                if (at(":")) {
                    next()
                    while (true) {
                        supertypes += type()
                        if (at("(") && !peek.newlineBefore) { next(); while (!at(")")) { expression(); if (at(",")) next() }; next() }
                        if (at(",")) next() else break
                    }
                }
                val body = if (at("{") && !peek.newlineBefore) block() else null
                return Decl("class", name, body, tok.line, supertypes = supertypes)
            }
            if (tok.type == T.IDENT) when (tok.text) {
                "import" -> { next(); val sb = StringBuilder(ident()); while (at(".") || at("*")) { sb.append(next().text); if (peek.type == T.IDENT && !peek.newlineBefore) sb.append(next().text) }; if (at("as", T.IDENT)) { next(); ident() }; return Decl("import", sb.toString(), null, tok.line) }
                "val", "var" -> {
                    next()
                    val name = ident()
                    val type = if (at(":")) { next(); type() } else null
                    val value = when {
                        at("=") -> { next(); expression() }
                        at("by", T.IDENT) -> { next(); expression() }
                        else -> null
                    }
                    return Decl(tok.text, name, value, tok.line, type = type)
                }
                "fun" -> {
                    next()
                    var name = ident()
                    while (at(".")) { next(); name = ident() }
                    expect("(")
                    while (!at(")")) { ident(); expect(":"); type(); if (at("=")) { next(); expression() }; if (at(",")) next() }
                    next()
                    if (at(":")) { next(); type() }
                    val body = when {
                        at("=") -> { next(); expression() }
                        at("{") -> block()
                        else -> err("expected a function body")
                    }
                    return Decl("fun", name, body, tok.line)
                }
            }
            return null
        }

        fun expressionStatement(): Node {
            val tok = peek
            val target = expression()
            if ((at("=") || at("+=") || at("-=")) ) {
                val op = next().text
                return Assign(target, op, expression(), tok.line)
            }
            return target
        }

        /** A type as written (`Provider<RegularFile>`, `String?`, `(Int) -> Unit` is not used here). */
        fun type(): String {
            val sb = StringBuilder(ident())
            while (at(".")) { next(); sb.append('.').append(ident()) }
            if (at("<")) { next(); sb.append('<'); while (!at(">")) { if (at("*")) { next(); sb.append('*') } else { if (at("out", T.IDENT) || at("in", T.IDENT)) next(); sb.append(type()) }; if (at(",")) { next(); sb.append(',') } }; next(); sb.append('>') }
            if (at("?")) { next(); sb.append('?') }
            return sb.toString()
        }

        fun block(): Lambda {
            val open = expect("{")
            val save = p
            val params = ArrayList<String>()
            // `{ a, b -> … }` or `{ it … }`
            run {
                val names = ArrayList<String>()
                while (peek.type == T.IDENT) { names += next().text; if (at(",")) next() else break }
                if (names.isNotEmpty() && at("->")) { next(); params += names } else p = save
            }
            val body = statements(T.OP, "}")
            expect("}")
            return Lambda(params, body, open.line)
        }

        private val binary = listOf(
            setOf("||"), setOf("&&"), setOf("==", "!="), setOf("<", ">", "<=", ">=", "in", "!in", "is", "as"),
            setOf("?:"), setOf(".."), setOf("+", "-"), setOf("*", "/", "%"),
        )

        fun expression(): Node = binaryAt(0)

        /** Infix calls (`a to b`) bind between `?:` and `..`, as in Kotlin; kept at one level here. */
        fun binaryAt(level: Int): Node {
            if (level == binary.size) return infix()
            var left = binaryAt(level + 1)
            while (!peek.newlineBefore) {
                val op = peek.text
                if (op !in binary[level]) break
                if (op == "<" || op == ">") { /* comparison */ }
                val tok = next()
                left = if (op == "as" || op == "is") Binary(op, left, Name(type(), tok.line), tok.line) else Binary(op, left, binaryAt(level + 1), tok.line)
            }
            return left
        }

        fun infix(): Node {
            var left = prefix()
            while (peek.type == T.IDENT && !peek.newlineBefore && peek.text !in setOf("in", "is", "as", "else", "by")) {
                val tok = next()
                left = Binary(tok.text, left, prefix(), tok.line)
            }
            return left
        }

        fun prefix(): Node {
            if (at("!") || at("-") || at("+")) { val tok = next(); return Unary(tok.text, prefix(), tok.line) }
            return postfix(primary())
        }

        fun primary(): Node {
            val tok = peek
            return when {
                tok.type == T.STRING -> { next(); Str(tok.text.drop(1), tok.text[0] == 'P', tok.line) }
                tok.type == T.NUMBER -> { next(); Num(tok.text, tok.line) }
                tok.type == T.IDENT && tok.text == "if" -> {
                    next(); expect("("); val cond = expression(); expect(")")
                    val yes = if (at("{")) block() else expression()
                    val no = if (at("else", T.IDENT)) { next(); if (at("{")) block() else expression() } else null
                    Call(Name("if", tok.line), emptyList(), listOfNotNull(Arg(null, cond), Arg(null, yes), no?.let { Arg(null, it) }), null, tok.line)
                }
                tok.type == T.IDENT -> { next(); Name(tok.text, tok.line) }
                at("(") -> { next(); val e = expression(); expect(")"); e }
                at("{") -> block()
                at("::") -> { next(); Member(Name("", tok.line), ident(), tok.line) }
                else -> err("expected an expression")
            }
        }

        /** `<T>` after a name is a type argument list only when a call follows: `withType<Test>()`. */
        fun typeArgsAhead(): Boolean {
            if (!at("<") || peek.newlineBefore) return false
            var k = p + 1
            var depth = 1
            while (k < t.size && depth > 0) {
                val x = t[k]
                when {
                    x.type == T.OP && x.text == "<" -> depth++
                    x.type == T.OP && x.text == ">" -> depth--
                    x.type == T.IDENT || (x.type == T.OP && x.text in setOf(".", ",", "?", "*")) -> Unit
                    else -> return false
                }
                k++
            }
            return depth == 0 && k < t.size && t[k].type == T.OP && (t[k].text == "(" || t[k].text == "{") && !t[k].newlineBefore
        }

        fun postfix(start: Node): Node {
            var e = start
            while (true) {
                when {
                    (at(".") || at("?.")) -> { next(); e = Member(e, ident(), e.line) }
                    at("::") && !peek.newlineBefore -> { next(); e = Member(e, if (at("class", T.IDENT)) next().text else ident(), e.line) }
                    at("!!") && !peek.newlineBefore -> next()
                    typeArgsAhead() || (at("(") && !peek.newlineBefore) || (at("{") && !peek.newlineBefore && (e is Name || e is Member || e is Call)) -> {
                        val typeArgs = ArrayList<String>()
                        if (at("<")) { next(); while (!at(">")) { typeArgs += type(); if (at(",")) next() }; next() }
                        val args = ArrayList<Arg>()
                        if (at("(")) {
                            next()
                            while (!at(")")) {
                                val named = peek.type == T.IDENT && t[p + 1].type == T.OP && t[p + 1].text == "=" 
                                val name = if (named) next().text.also { next() } else null
                                args += Arg(name, expression())
                                if (at(",")) next() else if (!at(")")) err("expected ',' or ')'")
                            }
                            next()
                        }
                        val lambda = if (at("{") && !peek.newlineBefore) block() else null
                        // a call's trailing lambda after a Call node: `foo() { }` is one call
                        e = if (e is Call && e.lambda == null && args.isEmpty() && typeArgs.isEmpty() && lambda != null) e.copy(lambda = lambda) else Call(e, typeArgs, args, lambda, e.line)
                    }
                    at("[") && !peek.newlineBefore -> { next(); val i = expression(); expect("]"); e = Call(Member(e, "get", e.line), emptyList(), listOf(Arg(null, i)), null, e.line) }
                    else -> return e
                }
            }
        }
    }

    // --- queries ---

    /** Every node of [nodes], depth first, with the chain of enclosing calls (outermost first). */
    fun walk(nodes: List<Node>, visit: (Node, List<Call>) -> Unit) {
        fun go(n: Node, outer: List<Call>) {
            visit(n, outer)
            when (n) {
                is Call -> {
                    go(n.callee, outer)
                    n.args.forEach { go(it.value, outer) }
                    n.lambda?.let { l -> l.body.forEach { go(it, outer + n) } }
                }
                is Member -> go(n.receiver, outer)
                is Binary -> { go(n.left, outer); go(n.right, outer) }
                is Unary -> go(n.operand, outer)
                is Assign -> { go(n.target, outer); go(n.value, outer) }
                is Decl -> n.value?.let { v -> if (v is Lambda) v.body.forEach { go(it, outer) } else go(v, outer) }
                is Lambda -> n.body.forEach { go(it, outer) }
                else -> Unit
            }
        }
        nodes.forEach { go(it, emptyList()) }
    }

    /** `a.b.c` for a chain of names, calls written as `name()` or `name<T>()`: how a call reads in the script. */
    fun path(n: Node): String = when (n) {
        is Name -> n.name
        is Member -> path(n.receiver).let { if (it.isEmpty()) n.name else "$it.${n.name}" }
        is Call -> path(n.callee) + (if (n.typeArgs.isEmpty()) "" else n.typeArgs.joinToString(",", "<", ">")) + (if (n.args.isEmpty() && n.lambda != null) "" else "()")
        else -> "…"
    }

    /** The literal text of a string, or null when it is anything else. */
    fun literal(n: Node?): String? = (n as? Str)?.text
}
