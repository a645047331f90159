// Root of the Android Studio project; see settings.gradle.kts. Versions: gradle/libs.versions.toml.

// The release build's R8: Kotlin 2.4's metadata needs a newer R8 than the one AGP 8.7 bundles
// (gradle/compatibility.tsv), so the R8 of the Maven build (root pom.xml, r8.version) goes on the
// build script class path ahead of AGP's own, the way the R8 project documents for AGP.
buildscript {
    repositories {
        google()
        mavenCentral()
    }
    dependencies {
        // Also on Maven Central; written here, not in the catalog, since catalogs are not read inside buildscript {}.
        classpath("com.android.tools:r8:9.5.28")
    }
}

plugins {
    alias(libs.plugins.android.application) apply false
    alias(libs.plugins.kotlin.android) apply false
    alias(libs.plugins.kotlin.jvm) apply false
}

allprojects {
    group = "dev.motionfusion"
    version = "0.1.0"
}
