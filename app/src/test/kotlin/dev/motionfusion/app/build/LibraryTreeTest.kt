package dev.motionfusion.app.build

import dev.motionfusion.app.build.BuildFiles.child
import dev.motionfusion.app.build.BuildFiles.children
import dev.motionfusion.app.build.BuildFiles.text
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.w3c.dom.Element
import java.io.File

/**
 * android-libs and android-test-libs list the whole AndroidX tree by hand, because Maven cannot
 * follow AndroidX POMs (they name their AAR dependencies without a type). This test does what
 * Gradle would: it reads the POM of every listed library from the local Maven repository and
 * fails when a dependency some library asks for (compile or runtime scope) is missing from the
 * lists or listed older than asked, or older than a version constraint a listed POM publishes
 * for it. Kotlin's own libraries come from the root pom at versions at least as new as asked.
 */
class LibraryTreeTest {
    private data class Coordinates(val group: String, val artifact: String) {
        override fun toString() = "$group:$artifact"
    }

    private val root = BuildFiles.parse(File(BuildFiles.repositoryRoot, "pom.xml"))
    private val properties = root.child("properties")!!.children().associate { it.tagName to it.textContent.trim() }

    private fun listed(module: String): Map<Coordinates, String> =
        BuildFiles.parse(File(BuildFiles.repositoryRoot, "$module/pom.xml")).child("dependencies")!!.children("dependency").associate {
            Coordinates(it.text("groupId")!!, it.text("artifactId")!!) to it.text("version")!!
        }

    private val libraries = listed("android-libs") + listed("android-test-libs")

    /** What the root pom provides in place of what the AndroidX POMs ask for. */
    private val provided: Map<Coordinates, String> = mapOf(
        Coordinates("org.jetbrains.kotlin", "kotlin-stdlib") to properties.getValue("kotlin.version"),
        Coordinates("org.jetbrains.kotlin", "kotlin-stdlib-common") to properties.getValue("kotlin.version"),
        Coordinates("org.jetbrains.kotlin", "kotlin-stdlib-jdk7") to properties.getValue("kotlin.version"),
        Coordinates("org.jetbrains.kotlin", "kotlin-stdlib-jdk8") to properties.getValue("kotlin.version"),
        Coordinates("org.jetbrains.kotlinx", "kotlinx-coroutines-core") to properties.getValue("coroutines.version"),
        Coordinates("org.jetbrains.kotlinx", "kotlinx-coroutines-core-jvm") to properties.getValue("coroutines.version"),
        Coordinates("org.jetbrains.kotlinx", "kotlinx-coroutines-android") to properties.getValue("coroutines.version"),
        Coordinates("junit", "junit") to properties.getValue("junit4.version"),
    )

    /** Asked for by some POMs and deliberately not on the app's classpath. */
    private val notNeeded = mapOf(
        Coordinates("org.jetbrains", "annotations") to "compile-time annotations; kotlin-stdlib brings its own version",
        Coordinates("org.jetbrains.kotlinx", "atomicfu") to "coroutines 1.7's dependency; the coroutines version the app uses needs none at run time",
        Coordinates("org.jetbrains.kotlinx", "atomicfu-jvm") to "as atomicfu",
        Coordinates("org.hamcrest", "hamcrest-core") to "comes with junit 4 through the app's own test dependencies",
    )

    private fun pom(c: Coordinates, version: String): Element {
        val f = File(BuildFiles.localRepository, "${c.group.replace('.', '/')}/${c.artifact}/$version/${c.artifact}-$version.pom")
        assertTrue(f.isFile, "$f missing: the build resolves every listed library")
        return BuildFiles.parse(f)
    }

    @Test
    fun `every dependency any listed library asks for is listed at least at the version asked`() {
        assertTrue(libraries.size > 50, "the Material and AppCompat tree has more than 50 artifacts: $libraries")
        val problems = ArrayList<String>()
        for ((c, version) in libraries) {
            val p = pom(c, version)
            val asked = p.child("dependencies")?.children("dependency").orEmpty()
                .filter { (it.text("scope") ?: "compile") in setOf("compile", "runtime") && it.text("optional") != "true" }
            val constraints = p.child("dependencyManagement")?.child("dependencies")?.children("dependency").orEmpty()
            for (d in asked) {
                val dc = Coordinates(d.text("groupId")!!, d.text("artifactId")!!)
                val wanted = d.text("version")?.removePrefix("[")?.removeSuffix("]") ?: continue
                if (dc in notNeeded) continue
                val have = libraries[dc] ?: provided[dc]
                when {
                    have == null -> problems += "$c:$version asks for $dc:$wanted, which is not listed"
                    compareVersions(have, wanted) < 0 -> problems += "$c:$version asks for $dc:$wanted, listed at $have"
                }
            }
            for (d in constraints) {
                val dc = Coordinates(d.text("groupId")!!, d.text("artifactId")!!)
                val wanted = d.text("version") ?: continue
                val have = libraries[dc] ?: continue // a constraint applies only to what is in the tree
                if (compareVersions(have, wanted) < 0) problems += "$c:$version constrains $dc to $wanted, listed at $have"
            }
        }
        assertEquals(emptyList<String>(), problems)
    }

    @Test
    fun `each library is listed once, in one of the two lists`() {
        val main = listed("android-libs").keys
        val test = listed("android-test-libs").keys
        assertEquals(emptySet<Coordinates>(), main intersect test)
    }

    @Test
    fun `versions compare as Gradle orders them`() {
        assertTrue(compareVersions("1.10.0", "1.9.3") > 0)
        assertTrue(compareVersions("2.8.7", "2.8.7") == 0)
        assertTrue(compareVersions("1.1.0-alpha01", "1.1.0") < 0)
        assertTrue(compareVersions("9999.0-empty-to-avoid-conflict-with-guava", "1.0") > 0)
        assertTrue(compareVersions("1.0.0", "1.0") == 0)
    }

    companion object {
        /** Numeric parts compare as numbers; a qualifier after the numbers (alpha, beta, rc) sorts before the release. */
        fun compareVersions(a: String, b: String): Int {
            fun split(v: String): Pair<List<Int>, String?> {
                val numbers = v.substringBefore('-').split('.').map { it.toIntOrNull() ?: 0 }
                return numbers to v.substringAfter('-', "").ifEmpty { null }
            }
            val (na, qa) = split(a)
            val (nb, qb) = split(b)
            for (i in 0 until maxOf(na.size, nb.size)) {
                val c = na.getOrElse(i) { 0 }.compareTo(nb.getOrElse(i) { 0 })
                if (c != 0) return c
            }
            return when {
                qa == qb -> 0
                qa == null -> 1
                qb == null -> -1
                else -> qa.compareTo(qb)
            }
        }
    }
}
