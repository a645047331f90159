package dev.motionfusion.app.build

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.io.File

/**
 * Packages follow the data flow, in the app and in fusion-core: no two import each other, directly or through
 * others. Read from the import lines of each module's src/main (the app's generated resource
 * class R aside). In the app (sensor → settings → fusion, the capture engine → record → sessions …; live is the
 * live screen alone) the root package (the application, its object graph, the main activity) uses the others, none of them uses it; in
 * fusion-core the codecs (`io`) and the event stream (`event`, with the streams it names) use no
 * other package, and the formats, the filter's drivers and the calibration build on them.
 */
class PackageCycleTest {
    private val base = "dev.motionfusion.app"

    /** Package → the packages under [base] it imports. */
    internal fun dependencies(sources: File, base: String = this.base): Map<String, Set<String>> {
        val deps = HashMap<String, MutableSet<String>>()
        sources.walkTopDown().filter { it.isFile && it.extension == "kt" }.forEach { f ->
            val text = f.readLines()
            val pkg = text.firstOrNull { it.startsWith("package ") }?.removePrefix("package ")?.trim() ?: return@forEach
            val set = deps.getOrPut(pkg) { HashSet() }
            for (line in text) {
                if (!line.startsWith("import $base")) continue
                if (line.trim() == "import $base.R") continue // the generated resource table, not code
                val imported = line.removePrefix("import ").trim().substringBeforeLast('.')
                // A class nested in a class (import a.b.C.D) names its package by the lowercase parts.
                val p = imported.split('.').takeWhile { it.first().isLowerCase() }.joinToString(".")
                if (p != pkg && p.startsWith(base)) set += p
            }
        }
        return deps
    }

    /** One cycle among the packages of [deps], or null. */
    internal fun cycle(deps: Map<String, Set<String>>): List<String>? {
        val state = HashMap<String, Int>() // 1 on the path, 2 done
        val path = ArrayList<String>()
        fun visit(p: String): List<String>? {
            when (state[p]) {
                1 -> return path.subList(path.indexOf(p), path.size) + p
                2 -> return null
            }
            state[p] = 1
            path += p
            for (q in deps[p].orEmpty().sorted()) visit(q)?.let { return it }
            path.removeAt(path.size - 1)
            state[p] = 2
            return null
        }
        for (p in deps.keys.sorted()) visit(p)?.let { return it }
        return null
    }

    @Test
    fun `the app's packages import each other in one direction only`() {
        val main = File(BuildFiles.repositoryRoot, "app/src/main/kotlin")
        val deps = dependencies(main)
        assertTrue(deps.size >= 8, "packages found: ${deps.keys}")
        assertEquals(null, cycle(deps), "a cycle between packages")
    }

    @Test
    fun `fusion-core's packages import each other in one direction only`() {
        val core = dependencies(File(BuildFiles.repositoryRoot, "fusion-core/src/main/kotlin"), "dev.motionfusion.core")
        assertTrue(core.size >= 10, "packages found: ${core.keys}")
        assertEquals(null, cycle(core), "a cycle between fusion-core's packages")
    }

    @Test
    fun `the check finds a cycle when there is one`() {
        val tmp = kotlin.io.path.createTempDirectory("cycle").toFile()
        File(tmp, "A.kt").writeText("package $base.a\nimport $base.b.B\nclass A\n")
        File(tmp, "B.kt").writeText("package $base.b\nimport $base.c.C.Nested\nclass B\n")
        File(tmp, "C.kt").writeText("package $base.c\nimport $base.a.A\nclass C { class Nested }\n")
        assertEquals(listOf("$base.a", "$base.b", "$base.c", "$base.a"), cycle(dependencies(tmp)))
        File(tmp, "C.kt").writeText("package $base.c\nclass C { class Nested }\n")
        assertEquals(null, cycle(dependencies(tmp)))
        tmp.deleteRecursively()
    }
}
